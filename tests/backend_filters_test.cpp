// The filters and storages on every backend: both distance storages see the same shadows, soft filters give
// fractions, PCSS widens with the blocker's distance, the stored moments are the blur of the stored depths'
// moments, and the moments tunings keep the check.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "backends/common/storage_filter_tables.h"
#include "bench/truth/moments_check.h"
#include "tests/backend_fixture.h"

namespace omnishadow {
namespace {

TEST_P(BackendTest, BothStoragesSeeTheSameShadows) {
  Images linear = render(room_case(Technique::six_pass, Filter::hard, 512, Storage::linear_depth), 90);
  Images r32f = render(room_case(Technique::six_pass, Filter::hard, 512, Storage::r32f_distance), 90);
  size_t differing = 0;
  for (size_t i = 0; i < linear.shadow_factor.size(); ++i)
    differing += linear.shadow_factor[i] != r32f.shadow_factor[i];
  EXPECT_LT(differing, linear.shadow_factor.size() / 500)
      << "storages disagree on " << differing << " pixels";
  // Texels nothing was drawn to: none in a closed room, so both hold finite distances everywhere.
  for (const auto& face : r32f.cube_distance)
    EXPECT_LT(*std::max_element(face.begin(), face.end()), room_->light().far_plane);
}

TEST_P(BackendTest, SoftFiltersGiveFractionsBetweenZeroAndOne) {
  for (Filter f : {Filter::pcf_grid64, Filter::pcf_disk20, Filter::hw_compare2x2, Filter::pcss, Filter::vsm,
                   Filter::esm, Filter::evsm2, Filter::evsm4, Filter::msm}) {
    CaseConfig c = room_case(Technique::six_pass, f, 512, storage_for(f, Storage::linear_depth));
    if (Support s = backend_->supports(c); !s.ok) {
      std::cout << c.id() << " unsupported: " << s.reason << "\n";
      continue;
    }
    Images img = render(c);
    auto [lo, hi] = std::minmax_element(img.shadow_factor.begin(), img.shadow_factor.end());
    EXPECT_GE(*lo, 0.0f) << to_string(f);
    EXPECT_LE(*hi, 1.0f) << to_string(f);
    size_t partial = std::count_if(img.shadow_factor.begin(), img.shadow_factor.end(),
                                   [](float v) { return v > 0.0f && v < 1.0f; });
    EXPECT_GT(partial, 100u) << to_string(f) << " has no penumbra";
  }
}

// PCSS sizes its kernel by the penumbra, R (receiver - blocker) / blocker: a slab near the light (blocker 1.4
// from it, receiver 7.1: 0.4 world units of penumbra) casts a far wider soft edge than one near the floor
// (4.1 and 5.2: 0.025), while the disk PCF's kernel follows the viewer's distance only. Counted: floor pixels
// strictly between lit and shadowed under each slab's shadow (x < -1: the high slab's, x > 0: the low one's).
TEST_P(BackendTest, PcssPenumbraWidensWithTheBlockersDistance) {
  const scene::Scene slabs = scene::load_scene_text(R"({
      "camera": {"position": [-2, 20, 0], "target": [-2, 0, 0], "up": [0, 0, -1]},
      "light": {"position": [0, 5, 0], "far": 50},
      "objects": [{"type": "plane", "scale": [10, 1, 10]},
                  {"type": "box", "translate": [-1, 4, 0], "scale": [0.5, 0.05, 0.5]},
                  {"type": "box", "translate": [1, 1, 0], "scale": [0.5, 0.05, 0.5]}]})",
                                                    "slabs.json");
  backend_->load(slabs);
  auto soft_pixels = [&](Filter f) {
    CaseConfig c = room_case(Technique::six_pass, f, 1024);
    c.scene = "slabs";
    Images img = render(c);
    std::array<int, 2> count{0, 0};  // high slab's shadow, low slab's
    for (size_t i = 0; i < img.shadow_factor.size(); ++i) {
      const float* p = &img.world_position[4 * i];
      const float v = img.shadow_factor[i];
      if (p[3] != 1.0f || std::fabs(p[1]) > 1e-3f || v <= 0.0f || v >= 1.0f) continue;
      if (p[0] < -1.0f) ++count[0];
      if (p[0] > 0.0f) ++count[1];
    }
    return count;
  };
  const std::array<int, 2> pcss = soft_pixels(Filter::pcss), disk = soft_pixels(Filter::pcf_disk20);
  std::cout << "soft pixels under the high / low slab: pcss " << pcss[0] << " / " << pcss[1]
            << ", pcf_disk20 " << disk[0] << " / " << disk[1] << "\n";
  EXPECT_GT(pcss[0], 1000) << "the high slab's shadow has a wide penumbra";
  EXPECT_GT(pcss[0], 8 * std::max(pcss[1], 1)) << "high " << pcss[0] << ", low " << pcss[1];
  EXPECT_LT(disk[0], 8 * std::max(disk[1], 1))
      << "the disk PCF does not tell the slabs apart: high " << disk[0] << ", low " << disk[1];
}

// Every moments filter on the device: the moments it blurred and sampled are the blur of the moments of the
// depths it stored, within each step's rounding (bench/truth/moments_check.h), at 32 and 16 bits, over every
// face and seam.
TEST_P(BackendTest, StoredMomentsAreTheBlurOfTheStoredDepthsMoments) {
  int checked = 0;
  for (Filter f : all_values<Filter>()) {
    if (!traits(f).own_storage) continue;
    for (DepthFormat d : {DepthFormat::d32f, DepthFormat::d16}) {
      CaseConfig c = room_case(Technique::six_pass, f, 128, *traits(f).own_storage);
      c.depth_format = d;
      if (Support s = backend_->supports(c); !s.ok) {
        std::cout << c.id() << " unsupported: " << s.reason << "\n";
        continue;
      }
      const Images img = render(c, 7);
      const int channels = traits(c.storage).colour_channels;
      ASSERT_EQ(img.moment_channels, channels);
      const bench::MomentsReport r = bench::check_moments(img, c.storage, d);
      EXPECT_TRUE(r.ok()) << c.id() << ": " << bench::describe(r);
      EXPECT_EQ(r.values, 6u * 128u * 128u * unsigned(channels));
      ++checked;
    }
  }
  if (backend_->device().shares_host_memory) {
    EXPECT_EQ(checked, 10) << "llvmpipe and lavapipe run every moments filter at both precisions";
  }
}

// The extremes suite's tunings on the device: the moments check follows them (an exponent at 0.99 of the
// overflow limit with the far plane fitted, so z reaches 1 and e^(-2cz) is subnormal; VSM in world units),
// and bleed reduction only darkens: 1 - clamp((p - a) / (1 - a), 0, 1) >= 1 - p for every lit bound p, and
// somewhere in the room's penumbrae strictly.
TEST_P(BackendTest, MomentsTuningsKeepTheCheckAndBleedReductionOnlyDarkens) {
  struct Tuned {
    Filter filter;
    const char* tuning;
    bool fit;
  };
  for (const Tuned& t : {Tuned{Filter::evsm4, "exp0.99", true}, Tuned{Filter::esm, "exp0.99", true},
                         Tuned{Filter::vsm, "world", false}}) {
    CaseConfig c = room_case(Technique::six_pass, t.filter, 64, *traits(t.filter).own_storage);
    c.moments = parse_moments_tuning(t.tuning);
    c.optimizations.fit_range = t.fit;
    if (Support s = backend_->supports(c); !s.ok) GTEST_SKIP() << c.id() << " unsupported: " << s.reason;
    const Images img = render(c, 3);
    const bench::MomentsReport r = bench::check_moments(img, c.storage, c.depth_format, c.moments);
    EXPECT_TRUE(r.ok()) << c.id() << ": " << bench::describe(r);
  }
  CaseConfig plain = room_case(Technique::six_pass, Filter::vsm, 128, Storage::vsm_moments);
  CaseConfig reduced = plain;
  reduced.moments = parse_moments_tuning("lbr0.5");
  const Images a = render(plain, 3), b = render(reduced, 3);
  ASSERT_EQ(a.shadow_factor.size(), b.shadow_factor.size());
  size_t darker = 0;
  for (size_t i = 0; i < a.shadow_factor.size(); ++i) {
    ASSERT_GE(b.shadow_factor[i], a.shadow_factor[i] - 1e-6f) << "pixel " << i;
    darker += b.shadow_factor[i] > a.shadow_factor[i] + 0.01f;
  }
  EXPECT_GT(darker, 0u) << "the room's penumbrae have lit bounds below 0.5";
}

}  // namespace
}  // namespace omnishadow
