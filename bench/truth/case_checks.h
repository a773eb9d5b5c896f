#pragma once
// The checks of one case, as functions of its config, its images, the references it is held to and the
// options: each adds its reports and findings to the case's CaseFindings. Rendering the references, reading
// cubes back and writing files are the run floor's (bench/run/case_runner.h); a check that wants an image
// file hands its pixels to the context's write_image.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "backends/common/storage_filter_tables.h"
#include "bench/truth/findings.h"
#include "bench/truth/truth_cache.h"
#include "scenes/scene.h"

namespace omnishadow::bench {

// The default limit on a hard-filter case's misclassified pixels (--max-error not given). Correct cases
// measured here stay well below it (room 0.06-0.3%, heavy 1.3% at cube 512, the directional notes'
// scene 3.4%); a broken lookup (a flipped axis, no bias: 49% acne) is far above it.
inline constexpr double kDefaultHardMaxErrorPercent = 5.0;
// The default limit for the soft filters at the tutorials' kernel size (--pcf-scale 1): their penumbra is
// misclassified at the 0.5 threshold here and there (room 0.2-0.3%, heavy 2.9-5.1% at cube 256), while a
// kernel scaled by 10 (scripts/experiments/mutants.py) misclassifies 25-39% on heavy. A scale chosen with
// --pcf-scale has no default.
inline constexpr double kDefaultSoftMaxErrorPercent = 15.0;
// Which default a filter gets: hard for one depth comparison per lookup (hard, and hw_compare2x2, whose 2x2
// bilinear weighting of four 0/1 comparisons blurs only within one texel), soft for the PCF kernels.
inline bool has_hard_error_limit(Filter f) { return !traits(f).soft; }

// What the checks read from the run's options (bench/run/run_options.h extends it).
struct CheckOptions {
  int check_frame = 0;          // the frame whose images are written and compared
  double face_tolerance = 0.0;  // world units; single-pass faces are expected bit-identical to six_pass
  double lit_tolerance = 0.0;   // 8-bit levels per channel
  // Across backends (same case on another API) interpolation may differ in the last bits, which moves a PCF
  // sample across a texel edge now and then: a lit channel may differ by `cross_lit_tolerance` levels, a
  // shadow factor by `cross_shadow_tolerance` (0.1 = two of the disk's 20 samples), and up to
  // `cross_max_percent` of the values may exceed those before the check fails.
  double cross_lit_tolerance = 2.0;
  double cross_shadow_tolerance = 0.1;
  double cross_max_percent = 0.1;
  // A case whose shadow disagrees with exact visibility on more than this % of pixels is failed_quality, with
  // the measured error in its reason (the stability suite's "where a variant breaks"). Negative (not given):
  // hard-filter cases at kDefaultHardMaxErrorPercent, soft filters at the tutorials' scale at
  // kDefaultSoftMaxErrorPercent.
  double max_error_percent = -1.0;
  TruthOptions truth;  // the spherical light of the soft reference
};

// Where a check's image file goes: a path relative to the run's folder, and RGB rows top down.
using WriteImage =
    std::function<void(const std::string& relative_path, int width, int height, std::vector<uint8_t> rgb)>;

// What every check of a case reads besides its images: the scene it renders, the device's precision, the
// options, and the sink for its image files (empty: no files).
struct CheckContext {
  const scene::Scene& scene;
  const DeviceInfo& device;
  const CheckOptions& options;
  WriteImage write_image;
};

// The case every other case of its group is checked against (six_pass, no culling or caching), and the
// group's key.
CaseConfig reference_config(const CaseConfig& c);
std::string group_key(const CaseConfig& c);
// The cube's faces side by side in face order, one image (the cube_faces PNG and check).
// The full cube's faces, or the check grid's; a face outside `faces` (bit f = face f) is left 0.
std::vector<float> concat_faces(const Images& img, uint8_t faces = 0x3f);
int face_edge(const Images& img);  // texels a face edge in concat_faces

// Against exact ray casts (bench/truth/truth_checks.cpp): the cube's texels, a moments storage's moments, the
// 2D maps' texels, the lighting pass's lookups replayed, and the shadow against exact visibility (with the
// --max-error limits and the error heatmap).
void check_cube(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths);
void check_moment_cube(CaseFindings& r, const Images& images);
void check_maps(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths);
void check_lookups_of(CaseFindings& r, const Images& images, const CheckContext& ctx);
void check_accuracy(CaseFindings& r, const Images& images, const CheckContext& ctx, TruthCache& truths);
// The frame's camera (bench/truth/camera_check.cpp): every covered pixel's world position lands in that pixel
// through the camera the check frame has.
void check_camera(CaseFindings& r, const Images& images, const CheckContext& ctx);
// --optimize view, every light of the case at the check frame: no covered pixel within a light's range looks
// it up through a face the frame left out. Light k as planned: its position, range and faces drawn.
struct PlannedLight {
  int index;
  glm::vec3 position;
  float range;
  uint8_t faces;
  int face_size;
};
void check_view_culling(CaseFindings& r, const Images& images, const std::vector<PlannedLight>& lights,
                        const glm::vec3& camera);
// --optimize clusters: every light that reaches a covered pixel is in the pixel's cluster's list; the lists'
// figures into r.light_clusters.
void check_light_clusters(CaseFindings& r, const Images& images, const std::vector<PlannedLight>& lights,
                          const scene::Camera& camera);

// --update-budget's sequence: per frame, what each light's faces hold (Backend::face_frames) and which faces
// the frame reads (view culling's, else all six), with the error measured. Holds every face read to its
// light's path: it holds a position its light had (never nothing), it has not waited beyond the bound that
// refreshing the oldest stale faces first guarantees, and no frame after the first renders more faces than
// the budget. Fills r.staleness.
struct SequenceFrame {
  int frame = 0;
  std::vector<std::array<int, 6>> face_frames;  // per light
  std::vector<uint8_t> read_faces;              // per light
  double misclassified_percent = 0.0;
  uint64_t pixels = 0;
  // Per light, whether an atlas re-plan moved its block at this frame (atlas::plan_at against the frame
  // before): it renders whole, outside the budget, as a first render. Empty without re-plans.
  std::vector<uint8_t> relocated;
};
void check_update_budget(CaseFindings& r, const scene::Scene& scene, const std::vector<int>& lights,
                         const std::vector<SequenceFrame>& frames);
// Whether a light on `path` is anywhere else at some frame 1..last_frame than at frame 0.
bool moves_within(const scene::LightPath& path, int last_frame);

// Against other renderings (bench/truth/image_checks.cpp).
// The timed and the check lighting variants are two compilations of one shader; a GPU compiler may contract
// or reorder their float operations. Each colour channel is fp32 until the final 8-bit rounding, and
// reassociating the ~64 operations that lead to it moves it by at most 64 * 2^-24 relative, under 1e-3 of a
// level: a value may then round the other way (1 level) only when it lies within 1e-3 of a rounding boundary,
// 0.2% of values at most for any distribution of colours. So: no value may differ by more than 1 level, and
// at most 0.2% by 1. Another filter, no bias or another light count moves whole regions by many levels and
// fails both (tests/image_test.cpp).
inline constexpr double kTimedLitMaxPercent = 0.2;
CheckResult timed_variant_check(const std::vector<uint8_t>& timed, const std::vector<uint8_t>& check_variant);
void check_timed_variant(CaseFindings& r, const Images& images, const CheckContext& ctx);
// Whether the device's (or the host's) face hashes show the two cubes equal, so that their values need not
// be compared; otherwise check_against_reference needs both cubes in full.
bool cubes_equal_by_hash(const Images& images, const Images& reference);
// Whether a read-back distance at texel (s, t) of a layer is one a conformant rasteriser may store there
// (texel_admissible against the light's cube truth).
using TexelAdmissible = std::function<bool(int layer, int s, int t, double distance)>;
// Every technique against its group's six_pass rendering (`reference`, of reference_config(r.config)): cube
// faces, shadow factor, lit frame, with the driver's evidence when the images point at it. Where the
// technique's coverage may flip at triangle edges, `admissible` judges the texels that differ (empty: every
// difference fails).
void check_against_reference(CaseFindings& r, const Images& images, const Images& reference,
                             const CheckContext& ctx, const TexelAdmissible& admissible = {});
// The first API's lit frame and shadow factor of a case, for the same case on the other API.
struct CrossReference {
  std::string case_id;
  std::vector<uint8_t> lit;
  std::vector<float> shadow_factor;
};
void check_against_other_api(CaseFindings& r, const Images& images, const CrossReference& other,
                             const CheckContext& ctx);

}  // namespace omnishadow::bench
