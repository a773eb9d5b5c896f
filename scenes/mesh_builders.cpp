#include "scenes/mesh_builders.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
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
        v.push_back({a, a}); v.push_back({b, b}); v.push_back({d, d});
      }
      if (j != lat - 1) {
        v.push_back({b, b}); v.push_back({c, c}); v.push_back({d, d});
      }
    }
  }
  return v;
}

std::vector<MeshVertex> load_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open OBJ file " + path);
  std::vector<glm::vec3> positions, normals;
  std::vector<MeshVertex> out;
  std::string line;
  int line_number = 0;
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " + why);
  };
  auto resolve = [&](long index, size_t count) -> size_t {
    long resolved = index > 0 ? index - 1 : static_cast<long>(count) + index;  // OBJ allows negative indices
    if (index == 0 || resolved < 0 || resolved >= static_cast<long>(count)) fail("index out of range");
    return static_cast<size_t>(resolved);
  };
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v" || tag == "vn") {
      glm::vec3 p;
      if (!(ls >> p.x >> p.y >> p.z) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("expected three finite numbers");
      (tag == "v" ? positions : normals).push_back(p);
    } else if (tag == "f") {
      std::vector<MeshVertex> poly;
      std::string corner;
      bool has_all_normals = true;
      while (ls >> corner) {
        MeshVertex mv{};
        long vi = 0, ni = 0;
        size_t slash1 = corner.find('/');
        try {
          vi = std::stol(corner.substr(0, slash1));
          if (slash1 != std::string::npos) {
            size_t slash2 = corner.find('/', slash1 + 1);
            if (slash2 != std::string::npos && slash2 + 1 < corner.size()) ni = std::stol(corner.substr(slash2 + 1));
          }
        } catch (const std::exception&) {
          fail("bad face corner '" + corner + "'");
        }
        mv.position = positions[resolve(vi, positions.size())];
        if (ni != 0) mv.normal = normals[resolve(ni, normals.size())]; else has_all_normals = false;
        poly.push_back(mv);
      }
      if (poly.size() < 3) fail("face with fewer than 3 corners");
      for (size_t k = 1; k + 1 < poly.size(); ++k) {
        MeshVertex a = poly[0], b = poly[k], c = poly[k + 1];
        if (!has_all_normals) {
          glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
          float len = glm::length(n);
          n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);  // degenerate triangles keep a valid normal
          a.normal = b.normal = c.normal = n;
        }
        out.push_back(a); out.push_back(b); out.push_back(c);
      }
    }
  }
  if (out.empty()) throw std::runtime_error(path + ": no faces");
  return out;
}

}  // namespace omnishadow::scene
