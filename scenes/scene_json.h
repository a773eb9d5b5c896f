#pragma once
// The scene file's JSON as the loaders read it (scenes/scene_loader.cpp, scenes/scene_lights.cpp): every
// value with the JSON pointer that reached it, so that every error names the file and /objects/3/scale.
// Internal to scenes/.

#include <cmath>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "scenes/scene.h"

namespace omnishadow::scene::detail {

using nlohmann::json;

// A JSON value with the pointer that reached it, so that every error can name /objects/3/scale.
class Node {
 public:
  Node(const json& value, std::string pointer, const std::string& source)
      : value_(value), pointer_(std::move(pointer)), source_(source) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw SceneError(source_ + ": " + (pointer_.empty() ? "/" : pointer_) + ": " + why);
  }
  const json& value() const { return value_; }
  const std::string& pointer() const { return pointer_; }

  bool has(const char* key) const { return value_.contains(key); }
  Node at(const char* key) const {
    if (!value_.contains(key)) Node(value_, pointer_ + "/" + key, source_).fail("missing required field");
    return Node(value_.at(key), pointer_ + "/" + key, source_);
  }
  Node at(size_t index) const {
    return Node(value_.at(index), pointer_ + "/" + std::to_string(index), source_);
  }

  void expect_object(const std::set<std::string>& allowed) const {
    if (!value_.is_object()) fail("expected an object");
    for (const auto& [key, _] : value_.items())
      if (!allowed.count(key)) Node(value_[key], pointer_ + "/" + key, source_).fail("unknown field");
  }
  double number() const {
    if (!value_.is_number()) fail("expected a number");
    double v = value_.get<double>();
    if (!std::isfinite(v) || std::fabs(v) > 1e30) fail("number must be finite and below 1e30 in magnitude");
    return v;
  }
  double number_in(double lo, double hi) const {
    double v = number();
    if (v < lo || v > hi) {
      std::ostringstream s;
      s << "must be in [" << lo << ", " << hi << "], got " << v;
      fail(s.str());
    }
    return v;
  }
  int integer_in(int lo, int hi) const {
    if (!value_.is_number_integer()) fail("expected an integer");
    auto v = value_.get<long long>();
    if (v < lo || v > hi)
      fail("must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  bool boolean() const {
    if (!value_.is_boolean()) fail("expected true or false");
    return value_.get<bool>();
  }
  std::string string() const {
    if (!value_.is_string()) fail("expected a string");
    return value_.get<std::string>();
  }
  glm::vec3 vec3() const {
    if (!value_.is_array() || value_.size() != 3) fail("expected an array of 3 numbers");
    return {at(size_t{0}).number(), at(size_t{1}).number(), at(size_t{2}).number()};
  }
  // A position, shifted by the scene's origin in double before it becomes float (LoadOptions::rebase_origin).
  glm::vec3 position(const glm::dvec3& origin) const {
    if (!value_.is_array() || value_.size() != 3) fail("expected an array of 3 numbers");
    glm::dvec3 p(at(size_t{0}).number(), at(size_t{1}).number(), at(size_t{2}).number());
    return glm::vec3(p - origin);
  }
  // A scale: one positive number (uniform) or three.
  glm::vec3 scale() const {
    glm::vec3 s = value_.is_number() ? glm::vec3(static_cast<float>(number())) : vec3();
    if (!(s.x > 0.0f && s.y > 0.0f && s.z > 0.0f)) fail("scale must be > 0 on every axis");
    return s;
  }

 private:
  const json& value_;
  std::string pointer_;
  const std::string& source_;
};

}  // namespace omnishadow::scene::detail
