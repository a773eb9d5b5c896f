#include "backends/common/viewport_swizzle.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>
#include <string>

namespace omnishadow::cube {
namespace {

// Row `row` of a face's view matrix at the origin must be +-1 times one axis: that axis as a swizzle
// component.
SwizzleComponent axis_of_row(const glm::mat4& view, int row, float sign, int face) {
  for (int axis = 0; axis < 3; ++axis) {
    const float v = sign * view[axis][row];  // glm is column-major: view[column][row]
    if (v == 1.0f) return static_cast<SwizzleComponent>(2 * axis);
    if (v == -1.0f) return static_cast<SwizzleComponent>(2 * axis + 1);
  }
  throw std::logic_error("face " + std::to_string(face) + "'s view row " + std::to_string(row) +
                         " is not an axis: no viewport swizzle expresses it");
}

}  // namespace

std::array<FaceSwizzle, kFaceCount> face_swizzles() {
  // The projection's x and y scales are 1 / tan(45 degrees): exactly 1 in float, checked here so that a
  // change to face_projection() cannot silently make the swizzled faces differ from six_pass's.
  const glm::mat4 projection = face_projection(0.1f, 10.0f, DepthRange::zero_to_one);
  if (projection[0][0] != 1.0f || projection[1][1] != 1.0f || projection[2][3] != -1.0f)
    throw std::logic_error(
        "the face projection's x, y and w scales are not exactly 1: swizzles would not match it");
  std::array<FaceSwizzle, kFaceCount> out{};
  for (int f = 0; f < kFaceCount; ++f) {
    const glm::mat4 view = face_view(f, glm::vec3(0.0f));
    // clip x = view x, clip y = view y, clip w = -view z (the projection above).
    out[static_cast<size_t>(f)] = {axis_of_row(view, 0, 1.0f, f), axis_of_row(view, 1, 1.0f, f),
                                   SwizzleComponent::pos_w, axis_of_row(view, 2, -1.0f, f)};
  }
  return out;
}

uint32_t packed_swizzle_pair(int k) {
  const auto swizzles = face_swizzles();
  uint32_t bits = 0;
  for (int f = 2 * k; f < 2 * k + 2; ++f) {
    const FaceSwizzle& s = swizzles[static_cast<size_t>(f)];
    const uint32_t face = uint32_t(s.x) | uint32_t(s.y) << 3 | uint32_t(s.z) << 6 | uint32_t(s.w) << 9;
    bits |= face << (12 * (f - 2 * k));
  }
  return bits;
}

glm::vec4 apply_swizzle(const FaceSwizzle& swizzle, const glm::vec4& v) {
  auto pick = [&](SwizzleComponent c) {
    const uint32_t k = static_cast<uint32_t>(c);
    return (k & 1u) ? -v[static_cast<int>(k / 2)] : v[static_cast<int>(k / 2)];
  };
  return {pick(swizzle.x), pick(swizzle.y), pick(swizzle.z), pick(swizzle.w)};
}

}  // namespace omnishadow::cube
