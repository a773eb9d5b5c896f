#pragma once
// Runs the untimed part of every case: configure, render the check frame, read back, count work, hand the
// images to the checks (bench/truth/case_checks.h) with the references they are held to, and write the
// images. Timing is gbench_glue's job. Defined over case_runner.cpp (backends, admission, the check frame,
// work counted) and case_check_steps.cpp (the checks each light is held to, images written).

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "bench/run/async_writer.h"
#include "bench/run/case_result.h"
#include "bench/run/device_state.h"
#include "bench/run/run_options.h"
#include "bench/run/scene_library.h"
#include "bench/truth/case_checks.h"
#include "bench/truth/truth_cache.h"

namespace omnishadow::bench {

class Harness {
 public:
  explicit Harness(RunOptions options);
  ~Harness();
  const RunOptions& options() const { return options_; }

  // Creates the backend on first use; throws std::runtime_error when the API cannot be brought up.
  Backend& backend(const std::string& name);
  // Uses `backend` for `name` instead of the registry's (tests substitute scripted backends).
  void add_backend(const std::string& name, std::unique_ptr<Backend> backend);
  // The state of `name`'s device now (clocks, temperature, power); its probe is chosen when the backend comes
  // up.
  DeviceState sample_device(const std::string& name);
  std::string device_state_source(const std::string& name);
  // Locks `name`'s device clock until the harness is destroyed (run --lock-clocks); "" or why it cannot.
  std::string lock_clocks(const std::string& name);
  // The name cases use for a scene given by name or path: a bundled name is itself; a file (a scene file or a
  // model) is named by its stem, with characters other than letters, digits, '.', '_' and '-' made '_', so
  // that ids read gl/bunny/c512/... Later calls with that name load the file. Throws std::invalid_argument
  // when two different files would share a name.
  std::string add_scene(const std::string& name_or_path);
  // Loads (and caches) a scene by name or path (with --light / --camera applied); throws scene::SceneError.
  const scene::Scene& scene(const std::string& name_or_path, bool rebase_origin = false,
                            int tessellation = 1);
  // The scene a case renders (its remedies decide how it is loaded).
  const scene::Scene& scene_of(const CaseConfig& c) {
    return scene(c.scene, c.remedies.rebase_origin, c.tessellation);
  }
  // The case's scene posed at `frame` (its moving casters where that frame has them), as the truths and plans
  // of that frame read it. The harness owns every loaded scene; posing changes nothing else of it.
  scene::Scene& posed(const CaseConfig& c, int frame) {
    auto& sc = const_cast<scene::Scene&>(scene_of(c));
    sc.pose(frame);
    return sc;
  }
  // The point lights a case's checks read: light 0 and every stride-th (checked_lights), and where not every
  // light is checked, the one farthest from the camera for its range (at frame 0) too: the light that sizing
  // by screen coverage (--atlas-tiles by_distance) shrinks most, so that every layout's accuracy sees it
  // alike.
  std::vector<int> lights_to_check(const CaseConfig& c);
  // Makes `config` the backend's current case (loading its scene first if needed).
  Backend& activate(const CaseConfig& config);
  // The untimed part of a case. Never throws: failures become the result's status and reason.
  void prepare(CaseResult& result);
  // With async_images: waits for every image file submitted so far; returns the failures as (case id,
  // message).
  std::vector<std::pair<std::string, std::string>> drain_writes();

 private:
  int cold_frame(const CaseConfig& c);  // the index of a case's first frame after configure
  void render_check_frame(const CaseConfig& c, Backend& b);
  bool admit(CaseResult& result, Backend& b);
  // Also returns every light as planned at the check frame (view culling's check reads it).
  std::vector<PlannedLight> count_work(CaseResult& result, Backend& b, float light_far);
  void measure_floor(CaseResult& result, Backend& b);
  // What the checks read besides the images (bench/truth/case_checks.h); their image files go to write_later.
  CheckContext check_context(const CaseResult& result);
  void check_lights(CaseResult& result, Images& images, std::vector<std::pair<int, Images>>& others,
                    bool is_reference);
  // Point light `light`'s checks against truth and references, with the scene's focus on it.
  void check_light(CaseResult& result, Images& images, int light, bool is_reference);
  // Against six_pass and the other API, for point light `light`; may read the cubes again in full.
  void check_against_six_pass(CaseResult& result, Images& images, int light);
  // --staleness-frames: frames 0..N-1 from a fresh start, each frame's faces and error, held to the lights'
  // paths (check_update_budget). Leaves the backend on the case.
  void measure_staleness(CaseResult& result, Backend& b);
  CubeReadBack cube_read_back_for(const CaseConfig& config) const;
  void read_full_cube(const CaseConfig& config, Images& images, int light);
  Images read_light(Backend& b, const CaseConfig& config, int light);
  void count_non_finite(CaseResult& result, const Images& images);
  void measure_flicker(CaseResult& result, Backend& b, const Images& images);
  void check_against_other_backend(CaseResult& result, const Images& images, int light);
  void write_images(CaseResult& result, const Images& images);
  void write_later(const CaseResult& result, std::function<void()> write);  // now, or on the writer
  DeviceStateProbe& probe(const std::string& backend_name);

  RunOptions options_;
  std::map<std::string, std::unique_ptr<Backend>> backends_;
  std::vector<std::string> creation_order_;                          // of backends_: destroyed in reverse
  std::map<std::string, std::unique_ptr<DeviceStateProbe>> probes_;  // by backend
  std::map<std::string, std::string> loaded_scene_;                  // backend -> scene name it holds
  SceneLibrary scenes_;
  // The six_pass images of the latest case group (same case but technique), kept for the checks.
  std::string reference_key_;
  std::map<int, Images> references_;  // by point light (the checked ones)
  // The first backend's lit frame and shadow factor per case (id without the backend), for the cross-API
  // check.
  std::map<std::string, CrossReference> cross_;
  TruthCache truths_;                    // the exact references, shared by the cases that ask for the same
  std::unique_ptr<AsyncWriter> writer_;  // with async_images
  std::map<std::string, FrameTiming> floors_;  // by the axes a floor depends on
};

}  // namespace omnishadow::bench
