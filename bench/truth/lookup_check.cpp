#include "bench/truth/lookup_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <stdexcept>

#include "backends/common/embedded_files.h"
#include "backends/common/layouts.h"
#include "backends/common/storage_filter_tables.h"
#include "bench/truth/parallel_rows.h"

namespace omnishadow::bench {
namespace {

constexpr double kFloatUlp = 0x1p-24;         // binary32 unit roundoff
constexpr double kComparisonRelative = 1e-4;  // 1 part in 1e5 per operation, about ten operations
constexpr double kValueTolerance = 1e-6;      // shadow / N: one rounding of a value in [0, 1]
constexpr size_t kExamples = 5;

// The outcomes a tap may have: bit 0 "lit" possible, bit 1 "occluded" possible.
constexpr unsigned kLit = 1, kOccluded = 2;

// Face coordinates of `d` on face `face` (spec table 8.19, the same arithmetic as cube::direction_to_face but
// for a given face): sc, tc and the major axis' magnitude.
void face_terms(const glm::dvec3& d, int face, double& sc, double& tc, double& ma) {
  switch (face) {
    case 0:
      sc = -d.z, tc = -d.y, ma = d.x;
      break;
    case 1:
      sc = d.z, tc = -d.y, ma = -d.x;
      break;
    case 2:
      sc = d.x, tc = d.z, ma = d.y;
      break;
    case 3:
      sc = d.x, tc = -d.z, ma = -d.y;
      break;
    case 4:
      sc = d.x, tc = -d.y, ma = d.z;
      break;
    default:
      sc = -d.x, tc = -d.y, ma = -d.z;
      break;
  }
}

struct TapContext {
  const Images& images;
  double current;  // distance from the light to the pixel's surface point
  double bias;
  double subtexel;  // 2^-subTexelPrecisionBits
};

unsigned texel_outcomes(const TapContext& ctx, int face, int s, int t) {
  const int size = ctx.images.cube_size;
  const double stored = ctx.images.cube_distance[size_t(face)][size_t(t) * size_t(size) + size_t(s)];
  if (!std::isfinite(stored)) return kLit | kOccluded;
  if (stored >= 1e30) return kLit;  // r32f_distance's clear value: nothing drawn there
  const double x = ctx.current - ctx.bias - stored;
  const double tolerance = kComparisonRelative * (ctx.current + std::abs(ctx.bias) + std::abs(stored));
  if (x > tolerance) return kOccluded;
  if (x < -tolerance) return kLit;
  return kLit | kOccluded;
}

// Every outcome a lookup in direction `d` may have, given that the device's `d` may differ from this one by
// `error` in each component.
unsigned tap_outcomes(const TapContext& ctx, const glm::dvec3& d, double error) {
  const glm::dvec3 a = glm::abs(d);
  const double major = std::max({a.x, a.y, a.z});
  // No direction to speak of, or none at all (a non-finite position or far plane): any texel.
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || !std::isfinite(error) ||
      major <= 2.0 * error)
    return kLit | kOccluded;
  const int size = ctx.images.cube_size;
  // A face is a candidate when its axis is the major one however the components round, or when the point lies
  // within the sub-texel step of the edge it shares with the major face: a seamless cube's NEAREST lookup
  // that rounds a coordinate onto the edge reads the adjacent face's texel there (GL 4.5 8.13.1, Vulkan "Cube
  // Map Edge Handling").
  const double edge_band = major * 2.0 * ctx.subtexel / size;
  unsigned outcomes = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (a[axis] < major - 2.0 * error - edge_band || a[axis] <= 2.0 * error) continue;
    const int face = 2 * axis + (d[axis] >= 0.0 ? 0 : 1);
    double sc, tc, ma;
    face_terms(d, face, sc, tc, ma);
    // The texel coordinate u = (sc / ma + 1) size / 2 moves by the components' error through sc and ma, by
    // the division's 2.5 ulp and the scaling's roundings, and by the sampler's sub-texel precision.
    const double slack_s =
        0.5 * size * (error / ma * (1.0 + std::abs(sc / ma)) + 4.0 * kFloatUlp * (std::abs(sc / ma) + 1.0));
    const double slack_t =
        0.5 * size * (error / ma * (1.0 + std::abs(tc / ma)) + 4.0 * kFloatUlp * (std::abs(tc / ma) + 1.0));
    const double u = 0.5 * (sc / ma + 1.0) * size, v = 0.5 * (tc / ma + 1.0) * size;
    // Clamped as a double first (NaN to 0): the conversion of an out-of-range value to int would be
    // undefined.
    auto first = [size](double x) { return x >= 0.0 ? int(std::min(std::floor(x), double(size - 1))) : 0; };
    const double ds = slack_s + ctx.subtexel, dt = slack_t + ctx.subtexel;
    for (int t = first(v - dt); t <= first(v + dt); ++t)
      for (int s = first(u - ds); s <= first(u + ds); ++s) {
        outcomes |= texel_outcomes(ctx, face, s, t);
        if (outcomes == (kLit | kOccluded)) return outcomes;
      }
  }
  return outcomes;
}

// The kernel of shaders/shadow_filters.glsl for the filter: tap offsets from frag_to_light (times `scale`,
// which for pcf_disk20 depends on the pixel), and the tutorial bias.
struct Kernel {
  std::vector<glm::dvec3> offsets;
  bool scaled_per_pixel = false;  // pcf_disk20: radius (1 + view distance / far) / 25 x --pcf-scale
  double bias = 0.0;
};

// pcf_grid64's constants read from the shader's own text (shaders/shadow_filters.glsl): the half-width (times
// --pcf-scale), the divisor that gives the step, and the taps per axis. One copy of the kernel, as for the
// disk.
struct GridKernel {
  double offset = 0.0, step_divisor = 0.0;
  int steps = 0;
};

const GridKernel& grid_kernel() {
  static const GridKernel kernel = [] {
    const auto& files = embedded_files();
    auto it = files.find("shadow_filters.glsl");
    if (it == files.end()) throw std::runtime_error("lookup check: shadow_filters.glsl is not embedded");
    const std::string& text = it->second;
    const size_t start = text.find("#elif defined(FILTER_PCF_GRID64)");
    const size_t end = start == std::string::npos ? start : text.find("#elif", start + 1);
    if (end == std::string::npos)
      throw std::runtime_error("lookup check: the FILTER_PCF_GRID64 branch not found in shadow_filters.glsl");
    const std::string body = text.substr(start, end - start);
    static const std::regex offset(R"(grid_offset = ([0-9.]+) \* frame\.knobs\.y;)");
    static const std::regex step(R"(step_size = grid_offset / ([0-9.]+);)");
    static const std::regex loops(R"(for \(int ([xyz]) = 0; \1 < (\d+); \+\+\1\))");
    std::smatch m, n;
    if (!std::regex_search(body, m, offset) || !std::regex_search(body, n, step))
      throw std::runtime_error(
          "lookup check: pcf_grid64's grid_offset or step_size not found in shadow_filters.glsl");
    GridKernel g{std::stod(m[1]), std::stod(n[1]), 0};
    int axes = 0;
    for (auto it = std::sregex_iterator(body.begin(), body.end(), loops); it != std::sregex_iterator();
         ++it, ++axes) {
      const int steps = std::stoi((*it)[2]);
      if (axes > 0 && steps != g.steps)
        throw std::runtime_error("lookup check: pcf_grid64's axes differ in taps");
      g.steps = steps;
    }
    if (axes != 3 || g.steps < 1)
      throw std::runtime_error("lookup check: pcf_grid64's three tap loops not found");
    return g;
  }();
  return kernel;
}

Kernel kernel_for(const LookupInputs& in) {
  Kernel k;
  switch (in.filter) {
    case Filter::hard:
      k.offsets = {glm::dvec3(0.0)};
      k.bias = 0.05;
      break;
    case Filter::pcf_grid64: {
      const GridKernel& g = grid_kernel();
      const double offset = g.offset * in.pcf_scale, step = offset / g.step_divisor;
      for (int x = 0; x < g.steps; ++x)
        for (int y = 0; y < g.steps; ++y)
          for (int z = 0; z < g.steps; ++z)
            k.offsets.push_back(glm::dvec3(-offset) + step * glm::dvec3(x, y, z));
      k.bias = 0.05;
      break;
    }
    default:
      k.offsets = disk_directions();
      k.scaled_per_pixel = true;
      k.bias = 0.15;
      break;
  }
  if (in.bias == BiasMode::zero) k.bias = 0.0;
  return k;
}

}  // namespace

const std::vector<glm::dvec3>& disk_directions() {
  static const std::vector<glm::dvec3> table = [] {
    const auto& files = embedded_files();
    auto it = files.find("shadow_filters.glsl");
    if (it == files.end()) throw std::runtime_error("lookup check: shadow_filters.glsl is not embedded");
    const std::string& text = it->second;
    const size_t start = text.find("kDiskDirections[20] = vec3[](");
    const size_t end = start == std::string::npos ? start : text.find(");", start);
    if (end == std::string::npos)
      throw std::runtime_error("lookup check: kDiskDirections not found in shadow_filters.glsl");
    const std::string body = text.substr(start, end - start);
    static const std::regex vec(R"(vec3\(\s*(-?\d+)\s*,\s*(-?\d+)\s*,\s*(-?\d+)\s*\))");
    std::vector<glm::dvec3> out;
    for (auto m = std::sregex_iterator(body.begin(), body.end(), vec); m != std::sregex_iterator(); ++m)
      out.emplace_back(std::stod((*m)[1]), std::stod((*m)[2]), std::stod((*m)[3]));
    if (out.size() != 20)
      throw std::runtime_error("lookup check: kDiskDirections has " + std::to_string(out.size()) +
                               " entries, not 20");
    return out;
  }();
  return table;
}

std::string lookup_check_skip_reason(const CaseConfig& c, const Images& images, bool has_point_light) {
  if (!has_point_light) return "no point light";
  if (traits(c.layout).geometry.map != TexelMap::cube_faces)
    return std::string(to_string(c.layout)) + ": the replay knows the cube-map rule only";
  if (c.filter != Filter::hard && c.filter != Filter::pcf_grid64 && c.filter != Filter::pcf_disk20)
    return std::string(to_string(c.filter)) + " does not look up NEAREST distances";
  if (c.storage != Storage::linear_depth && c.storage != Storage::r32f_distance)
    return std::string(to_string(c.storage)) + " is converted along each tap's own direction";
  if (c.remedies.bias == BiasMode::slope || c.remedies.normal_offset)
    return "the slope bias and the normal offset read the surface normal, which is not read back";
  if (!images.has_full_cube()) return "the cube was not read back in full";
  return {};
}

LookupReport check_lookups(const Images& images, const LookupInputs& in) {
  const Kernel kernel = kernel_for(in);
  std::vector<double> offset_lengths;
  for (const glm::dvec3& o : kernel.offsets) offset_lengths.push_back(glm::length(o));
  const double n = double(kernel.offsets.size());
  // Per row, merged in row order afterwards: the same report (and examples) whatever the thread count.
  std::vector<LookupReport> rows(size_t(std::max(images.height, 0)));
  parallel_rows(images.height, [&](int y) {
    LookupReport& row = rows[size_t(y)];
    TapContext ctx{images, 0.0, kernel.bias, std::ldexp(1.0, -in.subtexel_bits)};
    for (int x = 0; x < images.width; ++x) {
      const size_t p = size_t(y) * size_t(images.width) + size_t(x);
      const float* wp = &images.world_position[4 * p];
      if (wp[3] != 1.0f) continue;
      const glm::dvec3 position(wp[0], wp[1], wp[2]);
      const glm::dvec3 to_surface = position - in.light;  // exact: a difference of two floats, in double
      const double scale =
          kernel.scaled_per_pixel
              ? (1.0 + glm::length(in.camera - position) / in.far_plane) / 25.0 * in.pcf_scale
              : 1.0;
      ctx.current = glm::length(to_surface);
      double low = 0.0, high = 0.0;
      // Beyond the light's range (its far plane) the lighting pass reports 0 whatever the taps read
      // (lighting.frag); within float rounding of it, either.
      const double range_error = 8.0 * kFloatUlp * ctx.current;
      const double range = images.light_far;
      const bool beyond = ctx.current > range + range_error;
      const bool at_range = !beyond && ctx.current >= range - range_error;
      for (size_t i = 0; i < kernel.offsets.size() && !beyond; ++i) {
        // The device rounds frag_to_light, the offset's terms and their sum: a few ulps of the operands'
        // size.
        const double error = 8.0 * kFloatUlp * (ctx.current + scale * offset_lengths[i]);
        const unsigned outcomes = tap_outcomes(ctx, to_surface + scale * kernel.offsets[i], error);
        if (outcomes == (kLit | kOccluded)) ++row.ambiguous_taps;
        if (outcomes == kOccluded) low += 1.0;
        if (outcomes & kOccluded) high += 1.0;
      }
      row.taps += kernel.offsets.size();
      ++row.pixels;
      if (beyond || at_range) low = 0.0;
      const float got = images.shadow_factor[p];
      if (got >= low / n - kValueTolerance && got <= high / n + kValueTolerance) continue;
      ++row.outside;
      if (row.examples.size() < kExamples) row.examples.push_back({x, y, got, low / n, high / n});
    }
  });
  LookupReport r;
  for (const LookupReport& row : rows) {
    r.pixels += row.pixels;
    r.outside += row.outside;
    r.taps += row.taps;
    r.ambiguous_taps += row.ambiguous_taps;
    for (const auto& e : row.examples)
      if (r.examples.size() < kExamples) r.examples.push_back(e);
  }
  return r;
}

std::string describe(const LookupReport& r) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "lookups: %llu of %llu pixels (%.4f%%) hold a shadow factor no allowed texel gives",
                static_cast<unsigned long long>(r.outside), static_cast<unsigned long long>(r.pixels),
                r.outside_percent());
  std::string out = buf;
  if (!r.examples.empty()) {
    const auto& e = r.examples.front();
    std::snprintf(buf, sizeof buf, "; first: pixel (%d, %d) got %.4f, allowed %.4f..%.4f", e.x, e.y,
                  double(e.got), e.low, e.high);
    out += buf;
  }
  return out;
}

}  // namespace omnishadow::bench
