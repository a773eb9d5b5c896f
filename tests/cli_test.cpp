// The omnishadow binary end to end: a small run writes results that Google Benchmark's compare.py reads and
// images; --check turns failed checks into exit code 1; model files, the default matrix, list and export.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "bench/io/file_io.h"
#include "tests/cli_support.h"

namespace omnishadow::cli_test {
namespace {

// `report --out` that cannot be written (a folder, a path under a missing folder): one line naming the option
// and the path, exit 2, no traceback and no temporary file left; a good --out gets one line, the report's
// path.
TEST(CliReport, AnOutThatCannotBeWrittenIsOneLineAndLeavesNoTemporaryFile) {
  const fs::path run_dir = scratch("report_run");
  fs::create_directories(run_dir);
  {
    std::ofstream(run_dir / "results.json")
        << R"({"omnishadow": {"format": "omnishadow-results/1", "cases": []}})";
  }
  const std::string missing = (scratch("report_nowhere") / "no" / "report.html").string();
  for (const std::string& out : {run_dir.string(), missing}) {
    const Outcome o = run("report " + run_dir.string() + " --out " + out);
    EXPECT_EQ(o.exit_code, 2) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_NE(o.err.find("--out " + out), std::string::npos) << o.err;
    EXPECT_EQ(o.err.find("Traceback"), std::string::npos) << o.err;
  }
  for (const auto& entry : fs::directory_iterator(run_dir))
    EXPECT_EQ(entry.path().filename(), "results.json") << "left behind: " << entry.path();
  // The report draws its figures with matplotlib: where it is missing the bad --out cases above still hold.
  if (std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "a good --out not tried: /usr/bin/python3 lacks matplotlib (Debian: python3-matplotlib)";
  const Outcome good = run("report " + run_dir.string() + " --out " + (run_dir / "r.html").string());
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_EQ(good.out + good.err, "report: " + (run_dir / "r.html").string() + "\n");
}

TEST_F(CliRun, SmallMatrixWritesResultsImagesAndSummary) {
  fs::path out = scratch("run");
  Outcome o =
      run("run --scene room --cube 64 --technique six_pass,geometry_shader,vs_layer "
          "--filter hard,hw_compare2x2 --storage linear_depth,r32f_distance --frames 2 --warmup 1 --check "
          "--light-radius 0.2 --light-samples 2 --repetition-ms 0 --warmup-ms 0 "
          "--out " +
          out.string() + " --benchmark_repetitions=2");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_NE(o.err.find("[check 12/12]"), std::string::npos) << "progress on stderr";
  // The run ends with one line saying how to see its report.
  const std::string last_line = "report: omnishadow report " + out.string() + ", then open " +
                                (out / "report.html").string() + " in a browser\n";
  ASSERT_GE(o.out.size(), last_line.size());
  EXPECT_EQ(o.out.substr(o.out.size() - last_line.size()), last_line) << o.out;
  auto j = results_of(out);
  const auto& cases = j["omnishadow"]["cases"];
  ASSERT_EQ(cases.size(), 12u);
  EXPECT_TRUE(j["omnishadow"]["complete"].get<bool>());
  EXPECT_FALSE(j["omnishadow"]["devices"]["gl"]["renderer"].get<std::string>().empty());
  EXPECT_TRUE(j["omnishadow"]["system"].contains("LP_NUM_THREADS"));
  EXPECT_TRUE(j["omnishadow"]["system"].contains("cpu_model"));
  int ok = 0, unsupported = 0;
  for (const auto& c : cases) {
    std::string status = c["status"];
    if (status == "unsupported") {
      ++unsupported;
      EXPECT_NE(c["reason"].get<std::string>(), "");
      continue;
    }
    ASSERT_EQ(status, "ok") << c.dump();
    ++ok;
    EXPECT_EQ(c["timing"]["repetitions"], 2);
    EXPECT_EQ(c["timing"]["timed_frames"], 4);
    EXPECT_TRUE(c["timing"]["shadow"]["cpu_wall_ms"]["median"].get<double>() > 0);
    EXPECT_TRUE(c["counters"]["shadow"]["draw_calls"].get<int>() > 0);
    EXPECT_TRUE(c["gpu_timer"].contains("reliable"));
    EXPECT_FALSE(c["device_state"]["source"].get<std::string>().empty());
    EXPECT_GT(c["floor"]["shadow_wall_ms"].get<double>(), 0.0);
    EXPECT_GT(c["floor"]["lighting_over_floor"].get<double>(), 0.0);
    EXPECT_EQ(c["device_state"]["samples"].size(), 4u) << "before and after each of 2 repetitions";
    EXPECT_TRUE(fs::exists(out / c["images"]["lit"].get<std::string>()));
    EXPECT_TRUE(fs::exists(out / c["images"]["cube_faces"].get<std::string>()));
    // --images failed (the default): PNGs for every case, float buffers only for cases that failed a check.
    EXPECT_FALSE(c["images"].contains("world_position")) << "float buffers of a passing case";
    EXPECT_FALSE(c["images"].contains("shadow_factor"));
    EXPECT_TRUE(fs::exists(out / c["images"]["shadow_factor_png"].get<std::string>()));
    EXPECT_TRUE(fs::exists(out / c["images"]["error_heatmap"].get<std::string>()));
    EXPECT_LT(c["accuracy"]["misclassified_percent"].get<double>(), 5.0);
    EXPECT_TRUE(c["accuracy"].contains("mae_sphere"));
    EXPECT_EQ(c["checks"][0]["name"], "timed_lit");  // the timed frame's colour is the checked one
    EXPECT_EQ(c["checks"].size(), c["axes"]["technique"] == "six_pass" ? 1u : 4u);
  }
  EXPECT_EQ(ok, 9);
  EXPECT_EQ(unsupported, 3);  // hw_compare2x2 with r32f_distance, for each of the three techniques
  // Google Benchmark entries: one per timed case and repetition, plus aggregates; each points at its case.
  // Unsupported cases are listed once per reason in the summary, not as an ERROR line per repetition.
  size_t entries = 0;
  for (const auto& b : j["benchmarks"]) {
    ASSERT_TRUE(b.contains("omnishadow_case")) << b.dump();
    entries += b["run_type"] == "iteration";
  }
  EXPECT_EQ(entries, 9u * 2u);
  EXPECT_EQ(o.out.find("ERROR OCCURRED"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("unsupported, 3 cases"), std::string::npos) << o.out;
  EXPECT_GT(j["omnishadow"]["phases"]["untimed_seconds"].get<double>(), 0.0);
  EXPECT_GT(j["omnishadow"]["phases"]["timed_seconds"].get<double>(), 0.0);
  EXPECT_NE(o.out.find("s untimed"), std::string::npos) << "the summary gives both parts' seconds";
  EXPECT_NE(o.out.find("Passes against their floor"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "summary.md"));
  EXPECT_NE(o.out.find("ratio to six_pass"), std::string::npos);

  // A second run into the same folder must not clobber the first.
  Outcome again = run("run --scene room --cube 64 --out " + out.string());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("already holds a run"), std::string::npos) << again.err;
}

// `omnishadow --version` names the commit the results record: the build's, taken at build time.
TEST_F(CliRun, VersionNamesTheCommitTheResultsRecord) {
  const fs::path out = scratch("version");
  const Outcome o =
      run("run --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames 1 "
          "--warmup 0 --images none --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const auto j = results_of(out);
  const std::string commit = j["omnishadow"]["commit"];
  const Outcome version = run("--version");
  EXPECT_EQ(version.exit_code, 0) << version.err;
  EXPECT_EQ(version.out.rfind("omnishadow " + commit, 0), 0u) << version.out << " against " << commit;
  EXPECT_NE(commit, "") << "results.json names no commit";
}

TEST_F(CliRun, CompareScriptReadsTwoRuns) {
  const char* compare = "/usr/share/benchmark/compare.py";
  if (!fs::exists(compare))
    GTEST_SKIP() << "Google Benchmark's compare.py not installed (Debian: libbenchmark-tools)";
  fs::path a = scratch("a"), b = scratch("b");
  for (const fs::path& out : {a, b})
    ASSERT_EQ(run("run --scene room --cube 32 --technique six_pass,geometry_shader --filter hard --frames 2 "
                  "--no-images --no-accuracy --out " +
                  out.string() + " --benchmark_repetitions=3")
                  .exit_code,
              0);
  fs::path log = scratch("compare.log");
  std::string cmd = std::string("/usr/bin/python3 ") + compare + " benchmarks " +
                    (a / "results.json").string() + " " + (b / "results.json").string() + " >" +
                    log.string() + " 2>&1";
  int status = std::system(cmd.c_str());
  std::string text = omnishadow::bench::read_file(log.string());
  ASSERT_EQ(WEXITSTATUS(status), 0) << text;
  EXPECT_NE(text.find("gl/room/c32/f800x600/geometry_shader/hard"), std::string::npos) << text;
  EXPECT_NE(text.find("U Test"), std::string::npos) << text;
}

// --no-timing: every check runs and judges the run, no case is timed, and compare still reads its images.
TEST_F(CliRun, NoTimingChecksEveryCaseAndTimesNone) {
  const fs::path out = scratch("no_timing");
  const std::string matrix = "run --backend " + available_backends() +
                             " --scene room --cube 64 --frame 64x48 --technique six_pass,geometry_shader "
                             "--filter hard --frames 2 --warmup 0 --no-images --check --no-timing";
  Outcome o = run(matrix + " --out " + out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const auto j = results_of(out);
  EXPECT_TRUE(j["benchmarks"].empty()) << j["benchmarks"].dump();
  EXPECT_EQ(j["omnishadow"]["repetition_policy"]["timed"], false);
  EXPECT_TRUE(j["omnishadow"]["phases"]["timed_seconds"].is_null());
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c["id"];
    EXPECT_FALSE(c.contains("timing")) << c["id"] << ": a case of a --no-timing run was timed";
    std::set<std::string> checks;
    for (const auto& check : c["checks"]) checks.insert(check["name"].get<std::string>());
    if (c["axes"]["technique"] == "geometry_shader") {
      EXPECT_TRUE(checks.count("cube_faces")) << c["id"] << ": not held to six_pass's faces";
    }
  }
  EXPECT_NE(o.out.find("Not timed (`--no-timing`)"), std::string::npos) << o.out;
  EXPECT_EQ(o.out.find("Shadow pass: median wall time"), std::string::npos)
      << "a time table with no time in it";
  // The checks' verdict is the run's: a quality limit no case meets fails it.
  const fs::path strict = scratch("no_timing_strict");
  EXPECT_EQ(run(matrix + " --max-error 0 --out " + strict.string()).exit_code, 1);
  EXPECT_EQ(results_of(strict)["omnishadow"]["cases"][0]["status"], "failed_quality");
  const Outcome compared =
      run("compare " + out.string() + " " + out.string() + " --out " + scratch("no_timing_compare").string());
  EXPECT_EQ(compared.exit_code, 0) << compared.out << compared.err;
  EXPECT_NE(compared.out.find("not timed"), std::string::npos) << compared.out;
}

// Rounds until the time is up; every case then holds its stability figure and its clock samples per
// repetition.
TEST_F(CliRun, SustainLoopsRoundsAndReportsStability) {
  fs::path out = scratch("sustain");
  Outcome o =
      run("run --scene room --cube 32 --frame 64x48 --technique six_pass,geometry_shader --filter hard "
          "--frames 2 --warmup 0 --no-accuracy --no-images --sustain 2 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  for (const auto& c : j["omnishadow"]["cases"]) {
    const auto& per = c["timing"]["per_repetition"];
    EXPECT_EQ(per["ended_by"], "sustain") << c["id"];
    EXPECT_GE(per["frame_ms"].size(), 2u) << "2 s of rounds hold more than one repetition of a 64x48 frame";
    EXPECT_EQ(c["device_state"]["samples"].size(), 2 * per["frame_ms"].size());  // before and after each
    EXPECT_GT(per["stability_percent"].get<double>(), 0.0);
  }
  EXPECT_NE(o.out.find("## Sustained run (2 s of rounds)"), std::string::npos) << o.out;
}

// --precision-metric gpu judges the timer-query time per repetition (compare --metric gpu's samples):
// recorded for every repetition whose GPU timer passed its check, and the interval reported is over those.
TEST_F(CliRun, PrecisionJudgesGpuTimeWhereTheTimerPassedItsCheck) {
  fs::path out = scratch("precision_gpu");
  Outcome o =
      run("run --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard,pcf_disk20 "
          "--frames 2 --warmup 1 --no-accuracy --no-images --precision 50 --precision-metric gpu "
          "--max-repetitions 9 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  EXPECT_EQ(j["omnishadow"]["repetition_policy"]["precision_metric"], "gpu");
  size_t reliable = 0;
  for (const auto& b : j["benchmarks"])
    if (b.value("run_type", "") == "iteration" && b.value("gpu_timer_reliable", 0.0) == 1.0) ++reliable;
  size_t gpu_samples = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    const auto& per = c["timing"]["per_repetition"];
    gpu_samples += per["frame_gpu_ms"].size();
    for (const auto& v : per["frame_gpu_ms"]) EXPECT_GT(v.get<double>(), 0.0) << c["id"];
    if (per["frame_gpu_ms"].size() >= 6u) {  // enough for an interval: it is the GPU time's
      EXPECT_EQ(per["median_interval_95"]["metric"], "frame_gpu_ms") << c["id"];
    } else {
      EXPECT_EQ(per["ended_by"], "cap") << c["id"] << ": too few GPU samples to judge, so the cap ends it";
    }
  }
  EXPECT_EQ(gpu_samples, reliable) << "one GPU sample per repetition whose timer passed its check";
  EXPECT_NE(o.out.find("median per-repetition frame GPU time"), std::string::npos) << o.out;
}

// Both APIs in one process, in either order, must exit cleanly: teardown of one may not break the other.
TEST_F(CliRun, TwoApiRunsExitZeroInEitherOrder) {
  std::string why;
  if (!vulkan_available(why)) GTEST_SKIP() << why;
  for (const char* order : {"gl,vulkan", "vulkan,gl"}) {
    fs::path out = scratch(std::string("two_api_") + order[0]);
    Outcome o = run(std::string("run --backend ") + order +
                    " --scene room --cube 32 --frame 64x48 "
                    "--technique six_pass --filter hard --frames 1 --warmup 0 --no-accuracy --out " +
                    out.string() + " --benchmark_repetitions=1");
    EXPECT_EQ(o.exit_code, 0) << order << ":\n" << o.err;
    EXPECT_TRUE(fs::exists(out / "results.json")) << order;
  }
}

// The default matrix does not ask a backend for a technique it cannot do at all; asked for by name, it is
// reported.
TEST_F(CliRun, DefaultMatrixLeavesOutWhatABackendCannotDo) {
  fs::path out = scratch("defaults");
  Outcome o =
      run("run --scene room --cube 32 --frame 64x48 --filter hard --frames 1 --warmup 0 --no-accuracy "
          "--images none --out " +
          out.string() + " --benchmark_repetitions=1");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  bool multiview_supported = o.err.find("multiview left out on gl") == std::string::npos;
  size_t cases = j["omnishadow"]["cases"].size();
  EXPECT_EQ(cases, multiview_supported ? 5u : 4u) << o.err;
  for (const auto& c : j["omnishadow"]["cases"]) EXPECT_EQ(c["status"], "ok") << c.dump();
  fs::path named = scratch("named");
  Outcome n =
      run("run --scene room --cube 32 --frame 64x48 --technique multiview --filter hard --frames 1 "
          "--warmup 0 --no-accuracy --images none --out " +
          named.string() + " --benchmark_repetitions=1");
  ASSERT_EQ(n.exit_code, 0) << n.err;
  auto k = results_of(named);
  ASSERT_EQ(k["omnishadow"]["cases"].size(), 1u);
  if (!multiview_supported) {
    EXPECT_EQ(k["omnishadow"]["cases"][0]["status"], "unsupported");
  }
}

// A run whose every backend renders on the CPU defaults to cube 512 only, said in one line; on a
// GPU, or with --cube given, the cube sizes are the GPU default or what was asked for.
TEST_F(CliRun, CpuDriversDefaultToOneCubeSizeAndSaySo) {
  const std::string common =
      " --scene room --frame 64x48 --technique six_pass --filter hard --frames 1 --warmup 0 "
      "--no-accuracy --images none --benchmark_repetitions=1 --out ";
  fs::path out = scratch("cpu_cube_default");
  Outcome o = run("run" + common + out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  std::set<int> sizes;
  for (const auto& c : j["omnishadow"]["cases"]) sizes.insert(c["axes"]["cube_size"].get<int>());
  const bool cpu_driver = j["omnishadow"]["devices"]["gl"]["shares_host_memory"].get<bool>();
  const bool said = o.err.find("cube 512 only: --cube not given") != std::string::npos;
  EXPECT_EQ(said, cpu_driver) << o.err;
  const std::set<int> expected = cpu_driver ? std::set<int>{512} : std::set<int>{512, 1024};
  EXPECT_EQ(sizes, expected) << o.err;
  fs::path asked = scratch("cpu_cube_asked");
  Outcome a = run("run --cube 512,1024" + common + asked.string());
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(a.err.find("cube 512 only"), std::string::npos) << a.err;
  auto k = results_of(asked);
  EXPECT_EQ(k["omnishadow"]["cases"].size(), 2u);
}

// `export`: a run as Bencher's metric format and as github-action-benchmark's list, each timed case with its
// frame time (median, least and greatest repetition), its misclassified pixels and whether it is ok.
TEST_F(CliRun, ExportWritesBencherAndGithubActionBenchmarkFormats) {
  fs::path out = scratch("export_run");
  Outcome o = run(
      "run --backend gl --scene room --cube 16 --frame 32x24 --technique six_pass,geometry_shader"
      " --filter hard --frames 2 --warmup 0 --images none --max-error 100 --benchmark_repetitions=3 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const fs::path bmf = out / "bencher.json";
  o = run("export " + out.string() + " --format bencher --out " + bmf.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto b = nlohmann::json::parse(omnishadow::bench::read_file(bmf.string()));
  ASSERT_EQ(b.size(), 2u) << b.dump();
  for (const auto& [id, measures] : b.items()) {
    const auto& wall = measures["frame-wall-ms"];
    EXPECT_LE(wall["lower_value"].get<double>(), wall["value"].get<double>()) << id;
    EXPECT_LE(wall["value"].get<double>(), wall["upper_value"].get<double>()) << id;
    EXPECT_GT(wall["value"].get<double>(), 0.0) << id;
    EXPECT_TRUE(measures.contains("frame-cpu-ms")) << id;
    EXPECT_TRUE(measures["misclassified-percent"]["value"].is_number()) << id;
    EXPECT_EQ(measures["status-ok"]["value"], 1.0) << id;
  }
  o = run("export " + out.string() + " --format github-action-benchmark");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto g = nlohmann::json::parse(o.out);
  ASSERT_TRUE(g.is_array());
  int walls = 0;
  for (const auto& e : g) {
    EXPECT_TRUE(e["name"].is_string() && e["unit"].is_string() && e["value"].is_number()) << e.dump();
    if (e["name"].get<std::string>().find(" frame-wall-ms") != std::string::npos) {
      ++walls;
      EXPECT_EQ(e["unit"], "ms");
      EXPECT_TRUE(e["range"].is_string()) << e.dump();
    }
  }
  EXPECT_EQ(walls, 2);
}

// A model file (glTF or OBJ) given to --scene runs directly and passes its checks on both APIs, named by
// its file stem; the loader's time is in the results and the summary.
TEST_F(CliRun, ModelFilesRunDirectlyAndPassTheirChecksOnBothApis) {
  const std::string engine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
  if (!fs::exists(engine) || !fs::exists(bunny))
    GTEST_SKIP() << engine << " or " << bunny
                 << " missing: bash scripts/setup.sh installs assimp-testmodels and glmark2-data";
  const std::string backends = available_backends();
  fs::path out = scratch("models");
  Outcome o = run(
      "run --backend " + backends + " --scene " + engine + "," + bunny +
      " --cube 256 --frame 400x300 --technique six_pass,geometry_shader --filter hard,pcf_disk20 --frames 1"
      " --warmup 0 --images none --check --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  std::map<std::string, int> by_scene;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump();
    ++by_scene[c["id"].get<std::string>().substr(0, c["id"].get<std::string>().find("/c256"))];
  }
  EXPECT_EQ(by_scene["gl/2CylinderEngine"], 4);
  EXPECT_EQ(by_scene["gl/bunny"], 4);
  if (backends == "gl,vulkan") {
    EXPECT_EQ(by_scene["vulkan/bunny"], 4);
  }
  const auto& loads = j["omnishadow"]["phases"]["scene_loads"];
  ASSERT_EQ(loads.size(), 2u) << loads.dump();
  EXPECT_EQ(loads[1]["scene"], "bunny");
  EXPECT_EQ(loads[1]["triangles"], 69666 + 2) << "the bunny and its floor";
  EXPECT_GE(loads[1]["seconds"].get<double>(), 0.0);
  EXPECT_NE(omnishadow::bench::read_file((out / "summary.md").string()).find("Scenes loaded"),
            std::string::npos);
  size_t placed = 0;
  for (size_t at = o.err.find("placed by rule"); at != std::string::npos;
       at = o.err.find("placed by rule", at + 1))
    ++placed;
  EXPECT_EQ(placed, 2u) << "said once per scene, not per backend or case:\n" << o.err;

  // Placed by hand: recorded in the results, and still checked.
  fs::path hand = scratch("models_by_hand");
  Outcome h =
      run("run --backend gl --scene " + bunny +
          " --light 0.2,1.6,0.9,0.3,0,0 --camera 2,1,3,0,0,0 --cube 256 "
          "--frame 400x300 --technique six_pass --filter hard --frames 1 --warmup 0 --images none --check "
          "--benchmark_repetitions=1 --out " +
          hand.string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  auto k = results_of(hand);
  EXPECT_EQ(k["omnishadow"]["options"]["light"], "0.2,1.6,0.9,0.3,0,0");
  EXPECT_EQ(k["omnishadow"]["options"]["camera"], "2,1,3,0,0,0");
  EXPECT_NE(h.err.find("light by --light"), std::string::npos) << h.err;
}

// A default scene that cannot load (bunny.json without glmark2-data) is left out in one line and the matrix
// goes on; the same scene asked for by name is an error.
TEST_F(CliRun, DefaultSceneThatCannotLoadIsLeftOutInOneLine) {
  fs::path dir = scratch("scenes_without_packages");
  fs::create_directories(dir);
  const std::string box = R"({"light": {}, "objects": [{"type": "box", "scale": 5, "inside": true}]})";
  for (const char* name : {"room.json", "heavy.json"}) std::ofstream(dir / name) << box;
  std::ofstream(dir / "bunny.json")
      << R"({"light": {}, "objects": [{"type": "obj", "file": "/nonexistent/bunny.obj"}]})";
  const std::string common =
      " --cube 32 --frame 64x48 --technique six_pass --filter hard --frames 1 --warmup 0 "
      "--no-accuracy --images none --benchmark_repetitions=1 --scenes-dir " +
      dir.string();
  const fs::path out = scratch("default_left_out");
  Outcome o = run("run" + common + " --out " + out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  EXPECT_NE(o.err.find("scene bunny left out (not asked for by name)"), std::string::npos) << o.err;
  auto j = results_of(out);
  EXPECT_EQ(j["omnishadow"]["cases"].size(), 2u);
  Outcome named = run("run --scene bunny" + common + " --out " + scratch("named_bunny").string());
  EXPECT_EQ(named.exit_code, 2) << named.err;
  EXPECT_NE(named.err.find("/nonexistent/bunny.obj"), std::string::npos) << named.err;
}

TEST_F(CliRun, ListShowsWhatThisMachineSupports) {
  Outcome o = run("list");
  ASSERT_EQ(o.exit_code, 0);
  for (const char* s : {"gl:", "room:", "heavy:", "ogldev:", "hall: ", " 64 point lights",
                        "techniques: six_pass", "supported on gl", "  six_pass: linear_depth (hard, "})
    EXPECT_NE(o.out.find(s), std::string::npos) << s << " missing from:\n" << o.out;
  // What is supported, a line per technique, and the refused combinations counted: not a line for each of
  // the hundreds refused.
  EXPECT_LT(std::count(o.out.begin(), o.out.end(), '\n'), 80) << o.out;
}

}  // namespace
}  // namespace omnishadow::cli_test
