#pragma once
// Small pieces the model loaders (scenes/obj_loader.cpp, scenes/gltf_*.cpp) share.

#include <cmath>
#include <glm/glm.hpp>
#include <string>

namespace omnishadow::scene {

// The unit normal of triangle a, b, c (counter-clockwise), computed in double: edges and their cross product
// of float coordinates up to 3.4e38 neither overflow nor underflow there. A degenerate (zero-area) triangle
// gets +Y: any unit normal will do, it rasterises to nothing.
inline glm::vec3 face_normal(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double length = glm::length(n);
  return length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0.0f, 1.0f, 0.0f);
}

// A library's error text is often several lines; a one-line error keeps the first non-empty one.
inline std::string first_line(const std::string& text, const char* if_empty) {
  const size_t start = text.find_first_not_of("\n ");
  if (start == std::string::npos) return if_empty;
  const size_t end = text.find('\n', start);
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

}  // namespace omnishadow::scene
