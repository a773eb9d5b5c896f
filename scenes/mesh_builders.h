#pragma once
// Unit primitives in object space, as non-indexed counter-clockwise triangle lists with outward normals.
// Sizes follow the tutorials: the box spans [-1, 1]^3 (LearnOpenGL's renderCube), so "scale 5" gives the
// 10-unit room of the point-shadow tutorial.

#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace omnishadow::scene {

struct MeshVertex {
  glm::vec3 position;
  glm::vec3 normal;
};

std::vector<MeshVertex> make_box();    // [-1,1]^3, 12 triangles
std::vector<MeshVertex> make_plane();  // [-1,1]^2 in XZ, normal +Y, 2 triangles
std::vector<MeshVertex> make_sphere(int longitude_segments, int latitude_segments);  // radius 1

}  // namespace omnishadow::scene
