#include "scenes/mesh_builders.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace omnishadow::scene {
namespace {

void add_triangle(std::vector<MeshVertex>& out, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 n) {
  out.push_back({a, n});
  out.push_back({b, n});
  out.push_back({c, n});
}

// Two counter-clockwise triangles for the quad a-b-c-d (seen from the side `n` points to).
void add_quad(std::vector<MeshVertex>& out, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
  add_triangle(out, a, b, c, n);
  add_triangle(out, a, c, d, n);
}

}  // namespace

std::vector<MeshVertex> make_box() {
  std::vector<MeshVertex> v;
  v.reserve(36);
  // For each axis and sign, the face at coordinate s*1 with its two tangent axes ordered so that
  // cross(u, w) points along the outward normal, keeping every triangle counter-clockwise from outside.
  for (int axis = 0; axis < 3; ++axis) {
    for (float s : {1.0f, -1.0f}) {
      glm::vec3 n(0.0f);
      n[axis] = s;
      glm::vec3 u(0.0f), w(0.0f);
      u[(axis + 1) % 3] = 1.0f;
      w[(axis + 2) % 3] = s;  // flipping w on the negative face keeps cross(u, w) == n
      add_quad(v, n - u - w, n + u - w, n + u + w, n - u + w, n);
    }
  }
  return v;
}

std::vector<MeshVertex> make_plane() {
  std::vector<MeshVertex> v;
  const glm::vec3 n(0, 1, 0);
  add_quad(v, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, n);
  return v;
}

std::vector<MeshVertex> make_sphere(int lon, int lat) {
  std::vector<MeshVertex> v;
  v.reserve(static_cast<size_t>(lon) * lat * 6);
  const float pi = std::numbers::pi_v<float>;
  auto point = [&](int i, int j) {
    // Latitude j = 0 is the north pole (+Y); longitude runs counter-clockwise seen from +Y.
    float theta = pi * static_cast<float>(j) / static_cast<float>(lat);
    float phi = 2.0f * pi * static_cast<float>(i % lon) / static_cast<float>(lon);
    return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
  };
  for (int j = 0; j < lat; ++j) {
    for (int i = 0; i < lon; ++i) {
      glm::vec3 a = point(i, j), b = point(i, j + 1), c = point(i + 1, j + 1), d = point(i + 1, j);
      if (j != 0) {
        v.push_back({a, a});
        v.push_back({b, b});
        v.push_back({d, d});
      }
      if (j != lat - 1) {
        v.push_back({b, b});
        v.push_back({c, c});
        v.push_back({d, d});
      }
    }
  }
  return v;
}

}  // namespace omnishadow::scene
