// Runs that are split, compared and repeated: shards merged, compare's input and gates, experiment axes,
// warm-up and repetitions by time, clock locking.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "bench/io/file_io.h"
#include "tests/cli_support.h"

namespace omnishadow::cli_test {
namespace {

TEST_F(CliRun, ShardsMergeIntoTheSameRunAndCompareReadsIt) {
  fs::path full = scratch("full"), s0 = scratch("s0"), s1 = scratch("s1"), merged = scratch("merged");
  const std::string matrix =
      "run --scene room --cube 32 --technique six_pass,geometry_shader --filter hard,pcf_disk20 "
      "--frame 64x48 --frames 1 --warmup 0 --light-radius 0 ";
  ASSERT_EQ(run(matrix + "--out " + full.string()).exit_code, 0);
  ASSERT_EQ(run(matrix + "--shard 0/2 --out " + s0.string()).exit_code, 0);
  ASSERT_EQ(run(matrix + "--shard 1/2 --out " + s1.string()).exit_code, 0);
  Outcome m = run("merge " + merged.string() + " " + s0.string() + " " + s1.string());
  ASSERT_EQ(m.exit_code, 0) << m.err;
  auto j = results_of(merged);
  EXPECT_EQ(j["omnishadow"]["cases"].size(), 4u);
  // Deterministic rendering: the merged shards hold the full run's work and images exactly.
  Outcome c = run("compare --no-timing " + full.string() + " " + merged.string());
  EXPECT_EQ(c.exit_code, 0) << c.out << c.err;
  EXPECT_NE(c.out.find("4 cases compared"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("0 work changes, 0 image changes"), std::string::npos) << c.out;
  EXPECT_TRUE(j["omnishadow"]["complete"].get<bool>());
  Outcome twice = run("merge " + scratch("m2").string() + " " + s0.string() + " " + s0.string());
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("shard 0 is given twice"), std::string::npos) << twice.err;
  // A shard missing (an offline runner): the merged run is incomplete, names the shard, and compare fails.
  fs::path partial = scratch("partial");
  Outcome half = run("merge " + partial.string() + " " + s0.string());
  EXPECT_EQ(half.exit_code, 1) << "written, but not a whole run";
  EXPECT_NE(half.err.find("merge: INCOMPLETE: shard 1 missing"), std::string::npos) << half.err;
  auto p = results_of(partial);
  EXPECT_FALSE(p["omnishadow"]["complete"].get<bool>());
  EXPECT_EQ(p["omnishadow"]["missing_shards"], nlohmann::json::array({1}));
  Outcome lacking = run("compare --no-timing " + full.string() + " " + partial.string());
  EXPECT_EQ(lacking.exit_code, 1) << lacking.out;
  EXPECT_NE(lacking.out.find("missing (the merged run lacks shard [1])"), std::string::npos) << lacking.out;
}

TEST_F(CliRun, CompareRefusesBadInput) {
  Outcome missing = run("compare /nonexistent/a /nonexistent/b");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("cannot read"), std::string::npos) << missing.err;
  Outcome usage = run("compare only-one-argument");
  EXPECT_EQ(usage.exit_code, 2);
}

// The same-run experiment axes (scripts/experiments/sensitivity_same_run.py): every case once per injected
// value and replica, measured in the same rounds, each copy with its own id and its injected work recorded.
TEST_F(CliRun, ExperimentAxesRunEveryCopyInOneRun) {
  fs::path out = scratch("experiment");
  Outcome o =
      run("run --scene room --cube 32 --technique six_pass --filter hard --frames 1 --no-images "
          "--no-accuracy --inject-fragment-work 0,5 --replicas 2 --out " +
          out.string() + " --benchmark_repetitions=2");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  std::vector<std::string> ids;
  for (const auto& c : j["omnishadow"]["cases"]) {
    ids.push_back(c["id"]);
    EXPECT_EQ(c["axes"]["injected_fragment_work"],
              c["id"].get<std::string>().find("/inj5/") != std::string::npos ? 5 : 0);
  }
  EXPECT_EQ(j["omnishadow"]["options"]["injected_fragment_work"], nlohmann::json({0, 5}));
  const std::string root = "gl/room/c32/f800x600/six_pass/hard/linear_depth/d32f/";
  EXPECT_EQ(ids, (std::vector<std::string>{root + "inj0/rep0", root + "inj0/rep1", root + "inj5/rep0",
                                           root + "inj5/rep1"}));
  Outcome twice =
      run("run --scene room --cube 32 --inject-fragment-work 5,5 --out " + scratch("experiment2").string());
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("--inject-fragment-work: a value is given twice"), std::string::npos) << twice.err;
}

// --warmup-ms repeats the warm-up frames until that long (a GPU's clock ramps after each pause), cycling over
// the warm-up frames' indices so the timed frames stay the same frames (gbench_glue.cpp): the run's work and
// images are those of a run without it; and each backend's clock settles before its first timed repetition,
// said on stderr. Frames count 10 ms each (--inject-frame-ms), so the count is exact on any machine: 2
// frames, then 18 more to reach 200 ms, in each of 2 repetitions (HarnessTest holds the measured path,
// scripted).
TEST_F(CliRun, WarmupByTimeKeepsTheTimedFrames) {
  const std::string args =
      "run --backend gl --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard "
      "--frames 2 --warmup 2 --images all --no-accuracy --benchmark_repetitions=2 --out ";
  fs::path none = scratch("warmup_none"), timed = scratch("warmup_timed");
  Outcome a = run(args + none.string() + " --warmup-ms 0");
  Outcome b = run(args + timed.string() + " --warmup-ms 200 --inject-frame-ms 10");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.err.find("[settle] gl: clock "), std::string::npos) << b.err;
  auto warmup_frames = [](const fs::path& out) {
    auto j = results_of(out);
    return j["omnishadow"]["cases"][0]["timing"]["warmup_frames"].get<int>();
  };
  EXPECT_EQ(warmup_frames(none), 4) << "2 frames in each of 2 repetitions";
  EXPECT_EQ(warmup_frames(timed), 40) << "20 frames of 10 ms in each of 2 repetitions";
  Outcome same = run("compare " + none.string() + " " + timed.string() + " --no-timing --out " +
                     scratch("warmup_cmp").string());
  EXPECT_EQ(same.exit_code, 0) << same.out;
  Outcome bad = run(args + scratch("warmup_bad").string() + " --warmup-ms -5");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--warmup-ms"), std::string::npos) << bad.err;
}

// --repetition-ms sizes each case's repetitions by time (gbench_glue.cpp, size_repetitions): at least
// --frames timed frames, more until a repetition lasts that long. The plain run says --repetition-ms 0 (a CPU
// driver's default; a GPU's is 100 ms, which would add frames there). Frames count 10 ms each
// (--inject-frame-ms), so 400 ms is exactly 40 frames on any machine. The work per frame and the images are
// those of a run without it.
TEST_F(CliRun, RepetitionLengthInTimeAddsTimedFrames) {
  const std::string args =
      "run --backend gl --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard "
      "--frames 2 --warmup 1 --no-accuracy --benchmark_repetitions=2 --out ";
  fs::path plain = scratch("repetition_plain"), sized = scratch("repetition_sized");
  Outcome a = run(args + plain.string() + " --repetition-ms 0");
  Outcome b = run(args + sized.string() + " --repetition-ms 400 --inject-frame-ms 10");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  auto timing = [](const fs::path& out) {
    auto j = results_of(out);
    return j["omnishadow"]["cases"][0]["timing"];
  };
  EXPECT_EQ(timing(plain)["frames_per_repetition"], 2) << "--repetition-ms 0 keeps --frames";
  EXPECT_EQ(timing(plain)["timed_frames"], 4);
  EXPECT_EQ(timing(sized)["frames_per_repetition"], 40) << "400 ms of 10 ms frames";
  EXPECT_EQ(timing(sized)["timed_frames"], 80) << "every repetition the same length";
  Outcome same = run("compare " + plain.string() + " " + sized.string() + " --no-timing --out " +
                     scratch("repetition_cmp").string());
  EXPECT_EQ(same.exit_code, 0) << same.out;
  Outcome bad = run(args + scratch("repetition_bad").string() + " --repetition-ms -1");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--repetition-ms"), std::string::npos) << bad.err;
}

// --lock-clocks locks through NVML where this process may (then says so and the run goes on), and is a
// one-line refusal naming the option and the backend anywhere else (here: llvmpipe's clock is the CPUs'),
// before any case.
TEST_F(CliRun, LockClocksLocksThroughNvmlOrRefusesInOneLine) {
  // On an NVIDIA machine this would lock the GPU's clock, which is the machine owner's call (a lent or shared
  // GPU's settings are not ours): only where OMNISHADOW_TEST_LOCK_CLOCKS=1 says so.
  const char* allowed = std::getenv("OMNISHADOW_TEST_LOCK_CLOCKS");
  if (fs::exists("/dev/nvidiactl") && !(allowed && std::string(allowed) == "1"))
    GTEST_SKIP() << "an NVIDIA GPU is present and --lock-clocks would lock its clock: set "
                    "OMNISHADOW_TEST_LOCK_CLOCKS=1 on a machine whose clock settings are yours";
  fs::path out = scratch("lock_clocks");
  Outcome o =
      run("run --backend gl --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard "
          "--frames 1 --warmup 0 --no-accuracy --no-images --lock-clocks --out " +
          out.string());
  if (o.exit_code == 0) {
    EXPECT_NE(o.err.find("[lock-clocks] graphics clock locked at"), std::string::npos) << o.err;
    return;
  }
  EXPECT_EQ(o.exit_code, 2) << o.err;
  const std::string lines = error_lines(o.err);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 1) << o.err;
  EXPECT_NE(lines.find("omnishadow: error: --lock-clocks: gl: "), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(out / "results.json")) << "refused before any case ran";
}

// A gate file (scripts/experiments/sensitivity.py --write-gate) sets the test's metric, alpha and minimum
// effect; a bad one is a one-line error naming the file and the field.
TEST_F(CliRun, CompareTakesItsGateFromAGateFile) {
  fs::path a = scratch("gate_a");
  ASSERT_EQ(run("run --scene room --cube 32 --technique six_pass --filter hard --frames 2 --no-images "
                "--no-accuracy "
                "--out " +
                a.string() + " --benchmark_repetitions=3")
                .exit_code,
            0);
  auto write = [&](const std::string& name, const std::string& text) {
    fs::path p = scratch(name);
    std::ofstream(p) << text;
    return p.string();
  };
  const std::string good = write("gate.json", R"({"metric": "cpu", "alpha": 0.01, "min_effect": 0.25})");
  const fs::path cmp_dir = scratch("gate_cmp");
  Outcome same =
      run("compare " + a.string() + " " + a.string() + " --gate " + good + " --out " + cmp_dir.string());
  EXPECT_EQ(same.exit_code, 0) << same.err;
  auto cmp = nlohmann::json::parse(omnishadow::bench::read_file((cmp_dir / "comparison.json").string()));
  EXPECT_EQ(cmp["metric"], "cpu") << cmp.dump().substr(0, 400);
  EXPECT_DOUBLE_EQ(cmp["alpha"].get<double>(), 0.01);
  EXPECT_DOUBLE_EQ(cmp["min_effect"].get<double>(), 0.25);
  Outcome bad =
      run("compare " + a.string() + " " + a.string() + " --gate " + write("bad.json", R"({"alpha": "x"})"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.json: field 'alpha' missing or not a number"), std::string::npos) << bad.err;
  Outcome junk = run("compare " + a.string() + " " + a.string() + " --gate " + write("junk.json", "{"));
  EXPECT_EQ(junk.exit_code, 2);
  EXPECT_NE(junk.err.find("cannot read it as JSON"), std::string::npos) << junk.err;
}

}  // namespace
}  // namespace omnishadow::cli_test
