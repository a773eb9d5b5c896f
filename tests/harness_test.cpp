// The harness against a scripted backend: statuses, checks with their metrics and diff images,
// driver-evidence reasons, a failing case that does not stop the matrix, and results written for every case.

#include <benchmark/benchmark.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "backends/common/cube_summary.h"
#include "backends/common/shadow_plan.h"
#include "bench/io/file_io.h"
#include "bench/io/results_reader.h"
#include "bench/report/results_writer.h"
#include "bench/report/summary_table.h"
#include "bench/run/case_runner.h"
#include "bench/run/gbench_glue.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

// Renders nothing; returns images scripted per technique so that every check outcome can be produced.
class ScriptedBackend : public Backend {
 public:
  ScriptedBackend() {
    info_.api = "scripted";
    info_.renderer = "scripted";
    info_.max_cube_size = 4096;
  }
  Support supports(const CaseConfig& c) const override {
    if (c.technique == Technique::vs_layer) return {false, "scripted: no vs_layer"};
    return {};
  }
  void upload_scene(const scene::Scene&) override {}
  void upload_moving_objects() override {}
  void configure_case(const CaseConfig& c) override {
    if (c.technique == Technique::geometry_shader && c.filter == Filter::pcf_grid64)
      throw std::runtime_error("scripted failure while configuring");
    current_ = c;
    config_ = c;
  }
  FrameTiming render_frame(int, FrameKind) override {
    FrameTiming t;
    t.shadow = {0.5, 2.0, 1.5};
    t.lighting = {0.5, 3.0, 2.5};
    // With jitter: the frame time walks through a 7-step cycle (per-repetition means then differ).
    t.frame_wall_ms = 5.0 + jitter_ms * static_cast<double>(frames_rendered_++ % 7);
    return t;
  }
  FrameCounters count_frame_work(int) override {
    FrameCounters c;
    c.shadow.valid = true;
    c.shadow.primitives_submitted = current_.technique == Technique::six_pass ? 432 : 72;
    c.shadow.draw_calls = 6;
    return c;
  }
  void report_light(int light) override { reported.push_back(light); }
  Images read_back_images(CubeReadBack cube, int) override {
    Images img;
    img.width = 4;
    img.height = 3;
    img.lit_rgba8.assign(4 * 3 * 4, 100);
    img.shadow_factor.assign(12, 0.0f);
    img.world_position = seen_positions(img.width, img.height);
    img.cube_size = 4;
    for (size_t f = 0; f < 6; ++f) img.cube_distance[f].assign(16, static_cast<float>(f + 1));
    if (current_.technique == Technique::geometry_shader && current_.filter == Filter::pcf_disk20) {
      img.cube_distance[2][5] += 0.25f;  // one texel off
      img.lit_rgba8[0] = 90;
    }
    if (current_.technique == Technique::geometry_shader_instanced)
      for (size_t f = 1; f < 6; ++f) img.cube_distance[f] = img.cube_distance[0];  // every view in one face
    img.timed_lit_rgba8 = img.lit_rgba8;
    if (current_.technique == Technique::six_pass && current_.filter == Filter::pcf_grid64)
      img.timed_lit_rgba8[5] = 1;  // the timed variant lit one channel differently
    if (cube == CubeReadBack::sampled) {
      cube::summarize_on_host(img);  // standing in for the device's summary
      img.cube_distance = {};
    }
    ++read_backs_[cube == CubeReadBack::full];
    return img;
  }

  // Points on the rays through the pixel centres of the scene's camera (row 0 at clip y = -1), as a
  // renderer's read-back has them: the camera check holds them to it.
  std::vector<float> seen_positions(int width, int height) const {
    const scene::Camera& c = scene_->camera;
    const glm::mat4 inverse =
        glm::inverse(glm::perspectiveRH_NO(glm::radians(c.fov_y_degrees), float(width) / float(height),
                                           c.near_plane, c.far_plane) *
                     glm::lookAtRH(c.position, c.target, c.up));
    std::vector<float> p;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const glm::vec4 q = inverse * glm::vec4((float(x) + 0.5f) / float(width) * 2.0f - 1.0f,
                                                (float(y) + 0.5f) / float(height) * 2.0f - 1.0f, 0.5f, 1.0f);
        p.insert(p.end(), {q.x / q.w, q.y / q.w, q.z / q.w, 1.0f});
      }
    return p;
  }

  double jitter_ms = 0.0;
  std::vector<int> reported;         // the lights read back after the first, in order (report_light)
  std::array<int, 2> read_backs_{};  // [sampled, full]
  int frames_rendered() const { return frames_rendered_; }

 private:
  CaseConfig current_;
  int frames_rendered_ = 0;
};

class HarnessTest : public ::testing::Test {
 protected:
  void SetUp() override { start(RunOptions::ImagePolicy::failed); }
  // warmup_ms 0: the scripted device is a GPU (it does not share host memory), whose automatic 100 ms of
  // warm-up by time would render thousands of scripted frames; the test of that default asks for it (-1).
  void start(RunOptions::ImagePolicy images,
             RunOptions::CubeReadBackPolicy cube = RunOptions::CubeReadBackPolicy::automatic,
             double warmup_ms = 0, double repetition_ms = 0) {
    out_ = fs::temp_directory_path() / ("omnishadow_harness_" + std::to_string(::getpid()));
    fs::remove_all(out_);
    fs::create_directories(out_);
    RunOptions o;
    o.images = images;
    o.cube_read_back = cube;
    o.out_dir = out_.string();
    o.scenes_dir = OMNISHADOW_TEST_SCENES_DIR;
    o.frames = 3;
    o.warmup_frames = 1;
    o.warmup_ms = warmup_ms;
    o.repetition_ms =
        repetition_ms;  // 0: the counts these tests assert; the scripted device passes for a GPU
    o.settle_s = 0;     // the scripted device has no clock to settle
    harness_ = std::make_unique<Harness>(o);
    auto backend = std::make_unique<ScriptedBackend>();
    backend_ = backend.get();
    harness_->add_backend("gl", std::move(backend));
  }
  void TearDown() override { fs::remove_all(out_); }

  std::vector<CaseResult> prepare_all(const std::vector<Filter>& filters) {
    std::vector<CaseResult> results;
    for (Filter f : filters)
      for (Technique t : {Technique::six_pass, Technique::geometry_shader,
                          Technique::geometry_shader_instanced, Technique::vs_layer}) {
        CaseResult r;
        r.config.scene = "room";
        r.config.cube_size = 4;
        r.config.technique = t;
        r.config.filter = f;
        harness_->prepare(r);
        results.push_back(r);
      }
    return results;
  }

  fs::path out_;
  std::unique_ptr<Harness> harness_;
  ScriptedBackend* backend_ = nullptr;
};

TEST_F(HarnessTest, StatusesChecksAndDiffImages) {
  std::vector<CaseResult> r = prepare_all({Filter::hard, Filter::pcf_grid64, Filter::pcf_disk20});
  // hard: six_pass ok, geometry_shader ok, instanced failed_check (one face everywhere), vs_layer
  // unsupported.
  EXPECT_EQ(r[0].status, Status::ok);
  EXPECT_EQ(r[1].status, Status::ok) << r[1].reason;
  ASSERT_EQ(r[1].checks.size(), 4u);  // timed_lit, cube_faces, shadow_factor, lit
  for (const CheckResult& c : r[1].checks) EXPECT_TRUE(c.passed);
  EXPECT_EQ(r[0].checks.size(), 1u);  // six_pass itself: timed_lit only
  EXPECT_EQ(r[0].checks[0].name, "timed_lit");
  EXPECT_EQ(r[2].status, Status::failed_check);
  EXPECT_NE(r[2].reason.find("all six faces hold the same image"), std::string::npos) << r[2].reason;
  EXPECT_EQ(r[3].status, Status::unsupported);
  EXPECT_EQ(r[3].reason, "scripted: no vs_layer");
  // pcf_grid64: geometry_shader fails to configure; the cases after it still run.
  EXPECT_EQ(r[5].status, Status::failed);
  EXPECT_NE(r[5].reason.find("scripted failure"), std::string::npos);
  // six_pass pcf_grid64: the timed variant lit one channel differently from the check variant.
  EXPECT_EQ(r[4].status, Status::failed_check);
  EXPECT_NE(r[4].reason.find("timed_lit"), std::string::npos) << r[4].reason;
  EXPECT_FALSE(r[4].checks[0].passed);
  EXPECT_EQ(r[4].checks[0].difference.differing, 1u);
  EXPECT_EQ(r[6].status, Status::failed_check);
  // pcf_disk20: geometry_shader differs in one cube texel and one lit channel.
  const CaseResult& d = r[9];
  ASSERT_EQ(d.status, Status::failed_check);
  EXPECT_EQ(d.reason.find("all six faces"), std::string::npos)
      << "faces differ from each other: no driver hint";
  EXPECT_TRUE(d.checks[0].passed);  // timed_lit
  const CheckResult& faces = d.checks[1];
  EXPECT_EQ(faces.name, "cube_faces");
  EXPECT_FALSE(faces.passed);
  EXPECT_EQ(faces.difference.differing, 1u);
  EXPECT_EQ(faces.difference.total, 96u);
  EXPECT_FLOAT_EQ(static_cast<float>(faces.difference.max_abs), 0.25f);
  EXPECT_EQ(faces.against, "gl/room/c4/f800x600/six_pass/pcf_disk20/linear_depth/d32f");
  ASSERT_FALSE(faces.diff_image.empty());
  EXPECT_TRUE(fs::exists(out_ / faces.diff_image));
  EXPECT_TRUE(d.checks[2].passed);  // shadow factor identical
  EXPECT_FALSE(d.checks[3].passed);
  EXPECT_DOUBLE_EQ(d.checks[3].difference.max_abs, 10.0);
  EXPECT_TRUE(fs::exists(out_ / d.checks[3].diff_image));
  EXPECT_TRUE(fs::exists(out_ / d.images.at("lit")));
  // Default image policy: a failed check keeps the float buffers for examination; a passing case has PNGs
  // only.
  ASSERT_TRUE(d.images.count("world_position"));
  EXPECT_TRUE(fs::exists(out_ / d.images.at("world_position")));
  EXPECT_TRUE(fs::exists(out_ / d.images.at("shadow_factor")));
  EXPECT_TRUE(r[1].images.count("lit"));
  EXPECT_FALSE(r[1].images.count("world_position"));
}

// With only the device's summary read back, equal face hashes settle the comparison with six_pass and no cube
// comes back in full; where hashes differ both cubes are read in full and compared value by value, so the
// findings (and the driver's evidence, which needs every face) are the same as with full read-backs.
TEST_F(HarnessTest, SampledReadBackComparesHashesFirstAndReadsInFullOnlyWhatDiffers) {
  start(RunOptions::ImagePolicy::failed, RunOptions::CubeReadBackPolicy::sampled);
  std::vector<CaseResult> r = prepare_all({Filter::hard, Filter::pcf_disk20});
  EXPECT_EQ(r[0].cube_read_back, "sampled");
  ASSERT_EQ(r[1].status, Status::ok) << r[1].reason;
  EXPECT_EQ(r[1].cube_read_back, "sampled");
  ASSERT_EQ(r[1].checks[1].name, "cube_faces");
  EXPECT_EQ(r[1].checks[1].method, "hash");
  EXPECT_TRUE(r[1].checks[1].passed);
  EXPECT_EQ(r[1].checks[1].difference.total, 96u);
  // Every view in one face: read again in full, the driver's evidence still found.
  EXPECT_EQ(r[2].status, Status::failed_check);
  EXPECT_EQ(r[2].cube_read_back, "sampled+full");
  EXPECT_NE(r[2].reason.find("all six faces hold the same image"), std::string::npos) << r[2].reason;
  // One texel off: the same figures as a full read-back gives.
  const CaseResult& d = r[5];
  ASSERT_EQ(d.status, Status::failed_check);
  EXPECT_EQ(d.cube_read_back, "sampled+full");
  EXPECT_EQ(d.checks[1].method, "values");
  EXPECT_EQ(d.checks[1].difference.differing, 1u);
  EXPECT_FLOAT_EQ(static_cast<float>(d.checks[1].difference.max_abs), 0.25f);
  // Full read-backs: the three cases whose hashes differ (instanced in both groups, geometry_shader's one
  // texel) and the two six_pass references they were compared with, nothing else.
  EXPECT_EQ(backend_->read_backs_[1], 5);
}

// Findings accumulate: a quality finding is not overwritten by a later check failure, and the status is the
// worst.
TEST(CaseFindings, StatusIsTheWorstAndNoReasonIsLost) {
  CaseResult r;
  EXPECT_EQ(r.status, Status::ok);
  r.add({Status::failed_quality,
         "max_error",
         "shadow disagrees on 7% of pixels",
         {{"misclassified_percent", 7.0}}});
  EXPECT_EQ(r.status, Status::failed_quality);
  r.add({Status::failed_check, "cube_faces", "cube_faces differ", {}});
  EXPECT_EQ(r.status, Status::failed_check);
  r.add({Status::failed_quality, "max_error", "again", {}});
  EXPECT_EQ(r.status, Status::failed_check) << "a milder finding never lowers the status";
  ASSERT_EQ(r.findings.size(), 3u);
  EXPECT_EQ(r.reason, "shadow disagrees on 7% of pixels; cube_faces differ; again");
  EXPECT_TRUE(fails_run(Status::failed_quality));
  EXPECT_TRUE(fails_run(Status::resource_error));
  EXPECT_FALSE(fails_run(Status::unsupported));
  EXPECT_FALSE(fails_run(Status::interrupted));  // the run itself exits 130/143
}

// results.json's status text reads back as the Status that wrote it, for every status (the merge of a crashed
// run's parts decides its exit code from that text), and no other text names one.
TEST_F(HarnessTest, EveryStatusReadsBackFromItsName) {
  const Status all[] = {Status::ok,          Status::failed_quality, Status::failed_check,
                        Status::interrupted, Status::resource_error, Status::failed,
                        Status::crashed,     Status::unsupported};
  for (Status s : all) EXPECT_EQ(status_named(to_string(s)), s) << to_string(s);
  EXPECT_EQ(status_named("?"), std::nullopt);
  EXPECT_EQ(status_named("Crashed"), std::nullopt);
  EXPECT_EQ(status_named(""), std::nullopt);
}

// A case of eight lights reads back light 0 and every second light after it, and the light farthest from the
// camera for its range (the hall's eighth: the one sizing by screen coverage shrinks most), joins each one's
// findings and reports under its name, and counts the shadow plan of every light.
TEST_F(HarnessTest, ManyLightCasesCheckEveryStrideThLightAndPlanEveryLight) {
  CaseResult r;
  r.config.scene = "hall";
  r.config.cube_size = 4;
  r.config.layout = Layout::cube_array;
  r.config.light_count = 8;
  harness_->prepare(r);
  const scene::Scene& lamps = harness_->scene("hall");
  auto view_share = [&](int k) {  // range over distance from the camera at frame 0
    const scene::PointLight& l = lamps.point_lights[size_t(k)];
    return l.far_plane / glm::length(l.path.at(0) - lamps.camera.position);
  };
  for (int k = 0; k < 7; ++k) EXPECT_GT(view_share(k), view_share(7)) << "light " << k;
  EXPECT_EQ(backend_->reported, std::vector<int>({2, 4, 6, 7})) << r.reason;
  EXPECT_EQ(r.light_stride, 2);
  ASSERT_EQ(r.per_light.size(), 5u) << r.reason;
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(r.per_light[i].light, int(2 * i));
  EXPECT_EQ(r.per_light[4].light, 7);
  int pairs = 0;
  const scene::Scene& hall = harness_->scene("hall");
  for (int k = 0; k < 8; ++k) {
    const scene::PointLight& l = hall.point_lights[size_t(k)];
    const cube::ShadowDrawPlan plan = cube::plan_shadow_draws(
        hall, l.path.at(harness_->options().check_frame), l.near_plane, l.far_plane, false);
    for (const auto& list : plan.face_objects) pairs += int(list.size());
  }
  EXPECT_EQ(r.object_face_pairs, pairs) << "every light's faces and objects";
}

TEST_F(HarnessTest, ImagePolicyDecidesWhichFilesAreWritten) {
  start(RunOptions::ImagePolicy::all);
  std::vector<CaseResult> all = prepare_all({Filter::hard});
  ASSERT_EQ(all[1].status, Status::ok);
  for (const char* role : {"lit", "cube_faces", "shadow_factor", "world_position", "coverage"}) {
    ASSERT_TRUE(all[1].images.count(role)) << role;
    EXPECT_TRUE(fs::exists(out_ / all[1].images.at(role))) << role;
  }
  start(RunOptions::ImagePolicy::none);
  std::vector<CaseResult> none = prepare_all({Filter::hard, Filter::pcf_disk20});
  EXPECT_EQ(none[5].status, Status::failed_check);  // geometry_shader pcf_disk20: a cube texel differs
  for (const CaseResult& r : none) {
    EXPECT_TRUE(r.images.empty()) << r.config.id();
    for (const CheckResult& c : r.checks) EXPECT_TRUE(c.diff_image.empty());
  }
  EXPECT_FALSE(fs::exists(out_ / "images"));
}

// On a GPU the warm-up goes on by time (--warmup-ms, 100 ms by default) so the clock ramps after each pause;
// the timed frames stay as many as asked. The time is the device's own frame time (5 ms a scripted frame),
// never the host's clock: 100 ms is the --warmup frame and 19 more, on a fast machine and a loaded one alike.
TEST_F(HarnessTest, GpuWarmupGoesOnByTime) {
  start(RunOptions::ImagePolicy::none, RunOptions::CubeReadBackPolicy::automatic, -1.0);
  std::vector<CaseResult> results = prepare_all({Filter::hard});
  RepetitionPolicy two;
  two.repetitions = 2;
  run_timed(
      *harness_, results, two, (out_ / "raw.json").string(), [] {}, [] { return false; });
  int timed = 0;
  for (const CaseResult& r : results) {
    if (r.frames.empty()) continue;
    ++timed;
    EXPECT_EQ(r.frames.size(), 6u) << r.config.id() << ": 3 timed frames a repetition, warm-up aside";
    EXPECT_EQ(r.warmup.size(), 40u) << r.config.id()
                                    << ": 20 frames of 5 ms before each of the two repetitions";
  }
  ASSERT_GT(timed, 0);
}

// A slower device warms up in fewer frames: the warm-up ends at the first frame whose device time brings the
// sum to
// --warmup-ms (frames of 5 to 35 ms here: the scripted 7-step jitter), never earlier and never later.
TEST_F(HarnessTest, WarmupByTimeEndsAtTheFrameThatReachesIt) {
  start(RunOptions::ImagePolicy::none, RunOptions::CubeReadBackPolicy::automatic, 100.0);
  backend_->jitter_ms = 5.0;
  std::vector<CaseResult> results = prepare_all({Filter::hard});
  RepetitionPolicy one;
  one.repetitions = 1;
  std::vector<CaseResult> first(results.begin(), results.begin() + 1);
  run_timed(
      *harness_, first, one, (out_ / "raw.json").string(), [] {}, [] { return false; });
  ASSERT_FALSE(first[0].frames.empty()) << first[0].reason;
  const std::vector<FrameTiming>& w = first[0].warmup;
  ASSERT_GE(w.size(), 2u);
  double before_last = 0.0;
  for (size_t i = 0; i + 1 < w.size(); ++i) before_last += w[i].frame_wall_ms;
  EXPECT_LT(before_last, 100.0) << "the warm-up went on after reaching 100 ms";
  EXPECT_GE(before_last + w.back().frame_wall_ms, 100.0) << "the warm-up stopped short of 100 ms";
  EXPECT_LT(w.size(), 20u) << "longer frames, fewer of them than the 20 of 5 ms";
}

// A stop asked for in the middle of a repetition ends the run after that repetition, not after the round: the
// case in hand keeps all its timed frames, no later case of the round starts, and those are marked
// interrupted. Counted in the scripted device's frames: the stop comes at the second frame of the second
// case's repetition.
TEST_F(HarnessTest, StopEndsTheRunAfterTheRepetitionInHand) {
  std::vector<CaseResult> results = prepare_all({Filter::hard, Filter::pcf_disk20});
  RepetitionPolicy two;
  two.repetitions = 2;
  const int before = backend_->frames_rendered();
  const int per_repetition = 1 + 3;  // the --warmup frame, then --frames
  auto stop = [&] { return backend_->frames_rendered() >= before + per_repetition + 2; };
  run_timed(
      *harness_, results, two, (out_ / "raw.json").string(), [] {}, stop);
  int timed = 0, interrupted = 0;
  for (const CaseResult& r : results) {
    if (r.repetitions > 0) {
      ++timed;
      EXPECT_EQ(r.repetitions, 1) << r.config.id();
      EXPECT_EQ(r.frames.size(), 3u) << r.config.id() << ": the repetition in hand kept every timed frame";
    }
    if (r.status == Status::interrupted) ++interrupted;
  }
  EXPECT_EQ(timed, 2) << "the first case, and the one the stop came in";
  EXPECT_GT(interrupted, 0) << "the rest of the round was not timed";
  EXPECT_EQ(backend_->frames_rendered(), before + 2 * per_repetition) << "nothing rendered after the stop";
}

// On a GPU (the scripted device: 5 ms frames) a repetition lasts --repetition-ms, 100 by default: 20 frames,
// the same in every repetition; --frames stays the least.
TEST_F(HarnessTest, GpuRepetitionsLastLongEnoughInTime) {
  start(RunOptions::ImagePolicy::none, RunOptions::CubeReadBackPolicy::automatic, 0.0, -1.0);
  std::vector<CaseResult> results = prepare_all({Filter::hard});
  RepetitionPolicy two;
  two.repetitions = 2;
  run_timed(
      *harness_, results, two, (out_ / "raw.json").string(), [] {}, [] { return false; });
  int timed = 0;
  for (const CaseResult& r : results) {
    if (r.frames.empty()) continue;
    ++timed;
    EXPECT_EQ(r.frames_per_repetition, 20) << r.config.id() << ": 100 ms of 5 ms frames";
    EXPECT_EQ(r.frames.size(), 40u) << r.config.id();
  }
  ASSERT_GT(timed, 0);
}

TEST_F(HarnessTest, TimedRunKeepsEveryCaseAndWritesValidResults) {
  std::vector<CaseResult> results = prepare_all({Filter::hard, Filter::pcf_grid64});
  std::string raw = (out_ / "raw.json").string();
  int saves = 0;
  RepetitionPolicy two;
  two.repetitions = 2;
  run_timed(
      *harness_, results, two, raw, [&] { ++saves; }, [] { return false; });
  EXPECT_EQ(saves, 10);  // 5 timed cases x 2 repetitions (vs_layer unsupported twice, gs pcf_grid64 failed)
  for (const CaseResult& r : results) {
    if (r.status == Status::unsupported || r.status == Status::failed) {
      EXPECT_TRUE(r.frames.empty());
      continue;
    }
    EXPECT_EQ(r.frames.size(), 6u) << r.config.id();  // 3 frames x 2 repetitions
    EXPECT_EQ(r.warmup.size(), 2u);
    EXPECT_TRUE(r.gpu_timer.reliable);
  }
  RunInfo info;
  info.options = harness_->options();
  write_results((out_ / "results.json").string(), info, results, parse_gbench_json(read_file(raw)), true);
  auto j = nlohmann::json::parse(read_file((out_ / "results.json").string()));
  ASSERT_EQ(j["omnishadow"]["cases"].size(), 8u);
  EXPECT_EQ(j["omnishadow"]["cases"][5]["status"], "failed");
  EXPECT_EQ(j["omnishadow"]["cases"][0]["timing"]["shadow"]["gpu_ms"]["median"], 1.5);
  int errors = 0;
  for (const auto& b : j["benchmarks"]) errors += b.value("error_occurred", false);
  EXPECT_EQ(errors, 0);  // unsupported and failed cases are not handed to Google Benchmark (no ERROR lines)
  EXPECT_EQ(j["benchmarks"].size(), 5u * 2u + 5u * 4u);  // per repetition, and mean/median/stddev/cv
  for (const auto& b : j["benchmarks"]) {
    // Named as Google Benchmark names a case (no "/repeats:" from the rounds), numbered per case.
    EXPECT_EQ(b["name"].get<std::string>().find("repeats"), std::string::npos);
    if (b["run_type"] == "iteration") {
      EXPECT_LT(b["repetition_index"].get<int>(), 2);
    }
    if (b.value("aggregate_name", "") == "mean") {
      EXPECT_NEAR(b["real_time"].get<double>(), 5.0, 1e-9);  // the scripted frame time, in ms
    }
  }
  EXPECT_EQ(j["omnishadow"]["cases"][0]["timing"]["per_repetition"]["ended_by"], "count");
}

TEST_F(HarnessTest, PrecisionRepeatsUntilTheIntervalIsNarrowOrTheCap) {
  std::vector<CaseResult> results = prepare_all({Filter::hard});
  RepetitionPolicy policy;
  policy.precision_percent = 1.0;
  policy.max_repetitions = 9;
  run_timed(
      *harness_, results, policy, (out_ / "raw.json").string(), [] {}, [] { return false; });
  for (const CaseResult& r : results) {
    if (r.repetitions == 0) continue;
    // The scripted backend's frames all take the same time: the interval has no width once it is defined.
    EXPECT_EQ(r.repetitions, RepetitionPolicy::kMinForInterval) << r.config.id();
    EXPECT_EQ(r.repetitions_ended_by, "precision");
  }
  backend_->jitter_ms = 1.0;  // repetitions now differ by up to ~40%: +-1% is out of reach
  results = prepare_all({Filter::hard});
  run_timed(
      *harness_, results, policy, (out_ / "raw2.json").string(), [] {}, [] { return false; });
  EXPECT_EQ(results[0].repetitions, 9);
  EXPECT_EQ(results[0].repetitions_ended_by, "cap");
  EXPECT_LT(stability_percent(results[0].repetition_frame_ms), 97.0);
  const std::string summary = summary_markdown(results, {}, policy);
  EXPECT_NE(summary.find("cases hit the cap of 9"), std::string::npos) << summary;
  // A cell's p99 figure is a ratio to the median, and says so (not a bare number beside milliseconds).
  EXPECT_NE(summary.find(" ms (1.00x) p99/median "), std::string::npos) << summary;
}

// Case ids name a scene file by its stem (ids read gl/bunny/c512/..., not gl//tmp/x.json/...); two files that
// would share a name in one run are refused; a bundled name stays itself.
TEST_F(HarnessTest, ScenesGivenByPathAreNamedByTheirStem) {
  const fs::path dir = out_ / "models";
  fs::create_directories(dir / "b");
  const std::string box = R"({"light": {}, "objects": [{"type": "box"}]})";
  std::ofstream(dir / "My Model.json") << box;
  std::ofstream(dir / "b" / "room.json") << box;
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(harness_->add_scene("room"), "room");
  EXPECT_EQ(harness_->add_scene((dir / "My Model.json").string()), "My_Model");
  EXPECT_EQ(harness_->add_scene((dir / "tri.obj").string()), "tri");
  EXPECT_EQ(harness_->scene("tri").objects[0].kind, "obj") << "the name loads the file";
  EXPECT_EQ(harness_->scene("My_Model").source, (dir / "My Model.json").string());
  EXPECT_EQ(harness_->add_scene((dir / "tri.obj").string()), "tri") << "the same file again is no clash";
  EXPECT_THROW(harness_->add_scene((dir / "b" / "room.json").string()), std::invalid_argument);
}

}  // namespace
}  // namespace omnishadow::bench
