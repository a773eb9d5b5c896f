#pragma once
// What the checks of one case found: its status (the worst finding's), every finding, every image check with
// its figures, and the reports of the truths it was held to. The run floor's CaseResult extends it with what
// was timed and counted; the checks (bench/truth/case_checks.h) read and write only this part.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "backends/common/case_config.h"
#include "bench/truth/accuracy.h"
#include "bench/truth/cube_truth.h"
#include "bench/truth/image_compare.h"
#include "bench/truth/lookup_check.h"
#include "bench/truth/map_truth.h"
#include "bench/truth/moments_check.h"

namespace omnishadow::bench {

// A case's result code, the worst of its findings (dEQP's result codes are the model): users filter on these.
//   ok              every check passed
//   failed_quality  the shadow disagrees with exact visibility beyond --max-error (the measured error is a
//                   figure)
//   failed_check    a check failed: technique vs six_pass, timed vs check variant, across APIs, non-finite
//                   values
//   interrupted     the run was stopped (SIGINT/SIGTERM) before the case was timed
//   resource_error  the case does not fit in memory (predicted, or the allocation failed)
//   failed          an error: the API failed, the checking mode reported an API error, an exception
//   crashed         the process died (a signal: a driver's SIGSEGV or abort) or made no progress for
//                   --case-timeout-s while on this case; written by the supervisor
//                   (bench/cli/case_isolation.h), whose next worker process goes on from the next case
//   unsupported     the device or the technique cannot do the case; the matrix goes on
// Worse is later in that list, and unsupported stays last: status_named() searches up to it.
enum class Status {
  ok,
  failed_quality,
  failed_check,
  interrupted,
  resource_error,
  failed,
  crashed,
  unsupported
};
std::string_view to_string(Status s);
// The Status that to_string() spells `name` (as results.json carries it); nullopt for any other text.
std::optional<Status> status_named(std::string_view name);
// A case with this status makes `run --check` exit 1.
bool fails_run(Status s);

// One thing a check or a step found: what it does to the case, which check, a one-line message, and figures.
struct Finding {
  Status status = Status::failed;
  std::string
      check;  // timed_lit, cube_faces, cross_backend_lit, max_error, non_finite, memory, api, timing, ...
  std::string message;
  std::map<std::string, double> figures;
};

struct CheckResult {
  std::string
      name;  // timed_lit; cube_faces, shadow_factor, lit; cross_backend_lit, cross_backend_shadow_factor
  std::string against;  // id of the case compared with
  Difference difference;
  double tolerance = 0.0;    // per value
  double max_percent = 0.0;  // of values beyond the tolerance; 0 = none may differ
  double max_abs = -1.0;     // >= 0: and no value may differ by more than this (timed_lit: 1 level)
  bool passed = true;
  std::string diff_image;  // relative to out_dir, written on failure only
  // "values": compared value by value; "hash": the face hashes were equal, so were the values (cubes).
  std::string method = "values";
  // cube_faces of a pipeline whose coverage may flip at triangle edges: of the differing texels, those where
  // either value is not one a conformant rasteriser may store there (texel_admissible), which must be none;
  // unset where every difference counts alike, or where too many differ to be flips (judged unneeded).
  std::optional<uint64_t> inadmissible;
};

// A many-light case's reports for one of the point lights its checks read (the first, then every stride-th:
// checked_lights()), each held to that light's own truth.
struct LightReport {
  int light = 0;  // index into the scene's point lights
  std::optional<Accuracy> accuracy;
  std::optional<CubeTexelReport> cube_texels;
  std::optional<LookupReport> lookups;
};

// --optimize clusters: the lists the check frame's pixels read (bench/truth/frame_needs_checks.cpp).
struct LightClusterReport {
  int clusters = 0;
  int max_listed = 0;          // the longest list a covered pixel read
  double mean_listed = 0.0;    // lights a covered pixel's cluster lists, on average
  double mean_reaching = 0.0;  // lights that reach a covered pixel, on average
};

// --update-budget: a sequence of frames from a fresh start (bench/run/staleness_sequence.cpp), each frame's
// figures, and the worst and mean over the sequence. A face's wait: the frames, up to and including this one,
// that it was read (in view) while holding an older position of its light.
struct StalenessFrame {
  int frame = 0;
  int faces_rendered = 0;              // faces whose content is this frame's
  int faces_stale = 0;                 // faces read this frame that hold an older position of their light
  int max_wait = 0;                    // frames, the longest any face read this frame has waited
  double misclassified_percent = 0.0;  // the sequence's lights' pixels together, against this frame's truth
  uint64_t pixels = 0;
  int lights_relocated =
      0;  // lights an atlas re-plan moved this frame (each renders whole, outside the budget)
};
struct StalenessReport {
  std::vector<int> lights;  // the lights whose error is measured: those checked, and every one that moves
  std::vector<StalenessFrame> frames;
  int wait_bound = 0;  // frames no face may wait: ceil(units that can be stale / units a frame) - 1
  int max_wait = 0;    // over the sequence
  double mean_faces_rendered = 0.0;  // over the frames after the first (which renders every light whole)
  double mean_misclassified_percent = 0.0;
  double worst_misclassified_percent = 0.0;
  int worst_frame = 0;
};

struct CaseFindings {
  CaseConfig config;
  Status status = Status::ok;  // the worst finding's (ok without any)
  std::string reason;          // the findings' messages joined by "; " (one line); empty when ok
  std::vector<Finding> findings;
  // Adds a finding: the status becomes the worse of the two, the message joins the reason.
  void add(Finding finding);
  std::vector<CheckResult> checks;
  std::map<std::string, std::string> images;  // role -> path relative to out_dir
  std::optional<Accuracy> accuracy;           // against the ray-cast reference, for the check frame
  std::optional<MomentsReport>
      moments;  // a moments storage read back in full: its moments against its depths
  std::optional<CubeTexelReport>
      cube_texels;  // the cube against exact first-hit distances (bench/truth/cube_truth.h)
  std::optional<MapTexelReport>
      map_texels;  // spot/directional maps against exact depths (bench/truth/map_truth.h)
  // The lighting pass's lookups replayed from the read-back cube (bench/truth/lookup_check.h); the reason it
  // was not replayed otherwise (a technique other than six_pass is held to six_pass's shadow factor bit for
  // bit).
  std::optional<LookupReport> lookups;
  std::string lookups_skipped;
  // A case with several point lights: the lights checked (every light_stride-th from the first) and each
  // one's reports; `accuracy`, `cube_texels` and `lookups` above are then the first light's, except that
  // `accuracy` pools every checked light's pixels (pooled_accuracy).
  int light_stride = 1;
  std::vector<LightReport> per_light;
  // With every light checked (light_stride 1): the lit frame's PSNR from every light's shadow together
  // (lit_psnr_of_lights; -1 when identical to exact visibility's).
  std::optional<double> lit_psnr_every_light_db;
  std::optional<LightClusterReport> light_clusters;
  std::optional<StalenessReport> staleness;
};

// The point lights of a case with `light_count` lights whose images the checks read: every one up to
// kCheckedLights, else every stride-th from the first (the stride is ceil(light_count / kCheckedLights)).
inline constexpr int kCheckedLights = 4;
int checked_light_stride(int light_count);
std::vector<int> checked_lights(int light_count);
// Adds light `light`'s findings (checked on their own, `light_findings`) to the case: its messages prefixed
// "light k: ", its image checks named "<check>@l<k>", its reports into per_light.
void merge_light_findings(CaseFindings& into, int light, CaseFindings&& light_findings);
// Every checked light's accuracy over their pixels together: the percentages and mean errors averaged over
// all (light, pixel) pairs, the PSNRs from the pooled squared error. None where no light's accuracy was
// measured (--no-accuracy): a pooled zero would read as a case without error.
std::optional<Accuracy> pooled_accuracy(const std::vector<LightReport>& lights);

}  // namespace omnishadow::bench
