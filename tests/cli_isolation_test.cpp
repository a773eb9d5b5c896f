// A crashing or hanging driver costs one case (faults injected on both APIs); captures of the failed cases;
// one run per --out at a time.

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "bench/io/file_io.h"
#include "tests/cli_support.h"

namespace omnishadow::cli_test {
namespace {

// A run with faults injected into the cases that match `regex` (--inject-crash or --inject-hang) in the
// checks or the timed rounds, on both APIs where Vulkan is here: the matrix of 2 backends x 2 techniques.
struct FaultRun {
  Outcome outcome;
  nlohmann::json results;
};
FaultRun run_with_fault(const std::string& name, const std::string& fault) {
  const std::string backends = available_backends();
  const fs::path out = scratch(name);
  FaultRun f;
  f.outcome =
      run("run --backend " + backends +
          " --scene room --cube 16 --frame 32x24 --technique six_pass,geometry_shader "
          "--filter hard --frames 2 --warmup 0 --no-accuracy --images none --benchmark_repetitions=2 " +
          fault + " --out " + out.string());
  if (fs::exists(out / "results.json")) f.results = results_of(out);
  return f;
}

// Each case id to its status; the crashed ones' reasons checked by the caller.
std::map<std::string, nlohmann::json> cases_by_id(const nlohmann::json& results) {
  std::map<std::string, nlohmann::json> out;
  for (const auto& c : results["omnishadow"]["cases"]) out[c["id"].get<std::string>()] = c;
  return out;
}

// `attempts`: how many times each crashed case ran (a crash runs again once by default, a hang never).
void expect_one_case_each(const FaultRun& f, const std::string& reason_part, const std::string& step,
                          int attempts) {
  EXPECT_EQ(f.outcome.exit_code, 1) << f.outcome.err;
  ASSERT_TRUE(f.results.is_object()) << "results.json is kept: " << f.outcome.err;
  const auto cases = cases_by_id(f.results);
  int crashed = 0, ok = 0;
  for (const auto& [id, c] : cases) {
    if (id.find("/geometry_shader/") != std::string::npos) {
      ++crashed;
      EXPECT_EQ(c["status"], "crashed") << c.dump();
      EXPECT_NE(c["reason"].get<std::string>().find(reason_part), std::string::npos) << c.dump();
      EXPECT_EQ(c["crash"]["step"], step) << c.dump();
      EXPECT_EQ(c["crash"]["attempts"], attempts) << c.dump();
      if (attempts > 1) {
        EXPECT_NE(
            c["reason"].get<std::string>().find("at each of its " + std::to_string(attempts) + " attempts"),
            std::string::npos)
            << c.dump();
        ASSERT_EQ(c["crash"]["earlier"].size(), size_t(attempts - 1)) << c.dump();
        EXPECT_EQ(c["crash"]["earlier"][0]["signal"], "SIGSEGV") << c.dump();
      }
      EXPECT_EQ(c["axes"]["backend"], id.substr(0, id.find('/')))
          << "the crashed case's own axes: " << c.dump();
      EXPECT_EQ(c["axes"]["technique"], "geometry_shader") << c.dump();
    } else {
      ok += c["status"] == "ok";
    }
  }
  EXPECT_EQ(crashed, int(cases.size()) / 2) << "one crashed case per backend: " << f.outcome.err;
  EXPECT_EQ(ok, int(cases.size()) / 2) << "every other case finished: " << f.outcome.err;
  EXPECT_EQ(f.results["omnishadow"]["cases"].size(), cases.size()) << "each case once";
  EXPECT_TRUE(f.results["omnishadow"]["complete"].get<bool>())
      << "every case has its result, crashed ones included";
  // A fresh process after each attempt that crashed, unless it was the matrix's last case's last attempt.
  const bool last_crashed = f.results["omnishadow"]["cases"].back()["status"] == "crashed";
  EXPECT_EQ(f.results["omnishadow"]["worker_processes"].get<int>(),
            attempts * crashed + (last_crashed ? 0 : 1));
  EXPECT_TRUE(f.results["omnishadow"]["flaky_cases"].empty()) << "a case that crashes every time is no flake";
  std::vector<std::string> order;  // matrix order kept: each backend's six_pass before its geometry_shader
  for (const auto& c : f.results["omnishadow"]["cases"]) order.push_back(c["id"]);
  for (size_t i = 1; i < order.size(); i += 2)
    EXPECT_NE(order[i].find("/geometry_shader/"), std::string::npos) << order[i] << " out of matrix order";
  EXPECT_NE(f.outcome.out.find("## Crashed cases"), std::string::npos) << f.outcome.out;
}

}  // namespace

// A case that kills the process (SIGSEGV in its check frame, injected: --inject-crash) costs that case alone:
// run again in a fresh process (--crash-retries 1, the default) it dies again, so it is recorded `crashed`
// with the signal, the step and both attempts, the run goes on in a fresh process from the next case, every
// finished case is in results.json, and the run exits 1. On GL and Vulkan.
TEST_F(CliRun, ACrashInTheChecksCostsOneCase) {
  const FaultRun f = run_with_fault("crash_checks", "--inject-crash /geometry_shader/");
  expect_one_case_each(f, "SIGSEGV", "check_frame", 2);
  // The worker names the signal and its native frames before it dies (a driver's crash names its library).
  EXPECT_NE(f.outcome.err.find("omnishadow: worker died by SIGSEGV; native frames, innermost first:\n"),
            std::string::npos)
      << f.outcome.err;
}

// The same in the timed rounds: the cases timed before the crash keep their repetitions.
TEST_F(CliRun, ACrashInTheTimedRoundsCostsOneCase) {
  const FaultRun f =
      run_with_fault("crash_timed", "--inject-crash /geometry_shader/ --inject-in timed --crash-retries 0");
  expect_one_case_each(f, "SIGSEGV", "timed repetition", 1);
  for (const auto& [id, c] : cases_by_id(f.results)) {
    if (c["status"] == "ok") {
      EXPECT_GE(c["timing"]["repetitions"].get<int>(), 1) << id;
    }
  }
}

// A case that makes no progress for --case-timeout-s (a hang, injected: --inject-hang) is killed and recorded
// `crashed` with the timeout; the run goes on. The hang never ends, so it is always caught; 10 s is over ten
// times the longest step of these 16-texel cases here, so no other case is. The rule's timing (silence since
// the last line, not since the start) is SilenceWatch's test, on a clock that test drives.
TEST_F(CliRun, AHangIsKilledAfterTheCaseTimeoutAndCostsOneCase) {
  expect_one_case_each(run_with_fault("hang_checks", "--inject-hang /geometry_shader/ --case-timeout-s 10"),
                       "no progress for 10 s", "check_frame", 1);
}

// A flaky driver: the process dies in a case's first attempt only (--inject-attempts 1), in the checks or in
// the timed rounds. Run again in a fresh process the case finishes: it keeps that attempt's result with the
// first attempt's crash (`crashed_before`), results.json and the summary list it as flaky, and the run, every
// case ok, exits 0, as deqp-runner passes a pipeline whose failures passed when run again.
TEST_F(CliRun, ACaseThatCrashesOnceAndThenFinishesIsFlakyNotCrashed) {
  for (const std::string phase : {"checks", "timed"}) {
    SCOPED_TRACE(phase);
    const FaultRun f = run_with_fault("flaky_" + phase,
                                      "--inject-crash /geometry_shader/ --inject-attempts 1 "
                                      "--check --max-error 100 --inject-in " +
                                          phase);
    EXPECT_EQ(f.outcome.exit_code, 0) << f.outcome.err;
    ASSERT_TRUE(f.results.is_object()) << f.outcome.err;
    int flaky = 0;
    for (const auto& [id, c] : cases_by_id(f.results)) {
      EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
      if (id.find("/geometry_shader/") == std::string::npos) {
        EXPECT_FALSE(c.contains("crashed_before")) << id;
        continue;
      }
      ++flaky;
      ASSERT_EQ(c["crashed_before"].size(), 1u) << c.dump().substr(0, 2000);
      EXPECT_EQ(c["crashed_before"][0]["signal"], "SIGSEGV");
      EXPECT_EQ(c["crashed_before"][0]["step"], phase == "timed" ? "timed repetition" : "check_frame");
      if (phase == "timed") {
        EXPECT_GE(c["timing"]["repetitions"].get<int>(), 1) << "the second attempt's own repetitions";
      }
    }
    EXPECT_EQ(flaky, int(f.results["omnishadow"]["cases"].size()) / 2);
    EXPECT_EQ(f.results["omnishadow"]["flaky_cases"].size(), size_t(flaky));
    EXPECT_TRUE(f.results["omnishadow"]["crashed_cases"].empty());
    EXPECT_EQ(f.results["omnishadow"]["worker_processes"].get<int>(), 1 + flaky) << "a fresh one per crash";
    EXPECT_NE(f.outcome.out.find("## Flaky cases"), std::string::npos) << f.outcome.out;
    EXPECT_EQ(f.outcome.out.find("## Crashed cases"), std::string::npos) << f.outcome.out;
  }
}

// A stop asked for while a case hangs (SIGTERM 3 s into the run, as `timeout` sends it to a time-boxed run):
// the hung worker is killed at --case-timeout-s, its case recorded `crashed`, and no fresh process goes on to
// the cases left; results.json says the run stopped and is incomplete, and the run exits 143.
TEST_F(CliRun, AStopDuringAHangEndsTheRunAfterThatCase) {
  const fs::path out = scratch("stop_hang");
  const Outcome o =
      run("run --backend " + available_backends() +
              " --scene room --cube 16 --frame 32x24 --technique six_pass,geometry_shader --filter hard "
              "--frames 2"
              " --warmup 0 --no-accuracy --images none --benchmark_repetitions=1 --inject-hang /six_pass/"
              " --case-timeout-s 8 --out " +
              out.string(),
          "timeout --preserve-status -s TERM 3");
  EXPECT_EQ(o.exit_code, 128 + SIGTERM) << o.err;
  const nlohmann::json j = results_of(out);
  ASSERT_EQ(j["omnishadow"]["cases"].size(), 1u)
      << "no case after the hung one: " << j.dump().substr(0, 2000);
  EXPECT_EQ(j["omnishadow"]["cases"][0]["status"], "crashed");
  EXPECT_NE(j["omnishadow"]["cases"][0]["id"].get<std::string>().find("/six_pass/"), std::string::npos);
  EXPECT_FALSE(j["omnishadow"]["complete"].get<bool>());
  EXPECT_EQ(j["omnishadow"]["stopped_by"], "SIGTERM");
}

// --capture failed: after the matrix the failed cases run again, each alone in a process of its own, under a
// capture: on Vulkan GFXReconstruct's layer writes OUT/captures/<case>.gfxr, which gfxrecon-replay replays to
// the end; on GL RenderDoc captures the check frame (or, where it is not installed, the capture is
// `unsupported` naming its packages). captures.json and results.json list both. Every case fails here
// (--max-error 0.001), so both are selected; without --capture nothing is captured.
TEST_F(CliRun, CaptureRunsTheFailedCasesAgainUnderACapture) {
  std::string why;
  if (!vulkan_available(why)) GTEST_SKIP() << why;
  if (std::system("command -v gfxrecon-replay >/dev/null 2>&1") != 0 ||
      !fs::exists("/usr/share/vulkan/explicit_layer.d/VkLayer_gfxreconstruct.json"))
    GTEST_SKIP()
        << "GFXReconstruct is not installed (Debian package gfxreconstruct; scripts/setup.sh installs it)";
  const fs::path out = scratch("capture");
  const std::string args =
      "run --backend gl,vulkan --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard "
      "--frames 1 "
      "--warmup 0 --images none --benchmark_repetitions=1 --max-error 0.001 --out ";
  const Outcome o = run(args + out.string() + " --capture failed");
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const auto captures =
      nlohmann::json::parse(omnishadow::bench::read_file((out / "captures.json").string()))["captures"];
  ASSERT_EQ(captures.size(), 2u) << captures.dump(1);
  const auto results = results_of(out);
  EXPECT_EQ(results["omnishadow"]["captures"], captures);
  for (const auto& c : captures) {
    if (c["case"].get<std::string>().rfind("gl/", 0) == 0) {  // RenderDoc (tests/capture_replay_test.py)
      if (std::system("command -v renderdoccmd >/dev/null 2>&1") != 0) {
        EXPECT_EQ(c["status"], "unsupported") << c.dump();
        EXPECT_NE(c["reason"].get<std::string>().find("Debian packages renderdoccmd and librenderdoc"),
                  std::string::npos)
            << c.dump();
      } else {
        EXPECT_EQ(c["status"], "captured") << c.dump();
        EXPECT_EQ(c["tool"], "renderdoc");
        EXPECT_TRUE(fs::exists(out / c["file"].get<std::string>())) << c.dump();
      }
      continue;
    }
    ASSERT_EQ(c["status"], "captured") << c.dump();
    EXPECT_EQ(c["tool"], "gfxreconstruct");
    const fs::path file = out / c["file"].get<std::string>();
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_EQ(c["bytes"].get<uintmax_t>(), fs::file_size(file));
    EXPECT_NE(o.out.find("capture vulkan/room/c16/f32x24/six_pass/hard/linear_depth/d32f: captured"),
              std::string::npos)
        << o.out;
    const std::string replay =
        "gfxrecon-replay " + file.string() + " >" + (out / "replay.log").string() + " 2>&1";
    EXPECT_EQ(std::system(replay.c_str()), 0) << omnishadow::bench::read_file((out / "replay.log").string());
  }
  // GFXReconstruct named for a GL case: unsupported, with the tool that does capture GL.
  const fs::path gfxr_gl = scratch("capture_gfxr_gl");
  ASSERT_EQ(run(args + gfxr_gl.string() + " --capture failed --capture-tool gfxreconstruct").exit_code, 0);
  const auto named =
      nlohmann::json::parse(omnishadow::bench::read_file((gfxr_gl / "captures.json").string()));
  EXPECT_EQ(named["captures"][0]["status"], "unsupported");
  EXPECT_NE(named["captures"][0]["reason"].get<std::string>().find("GFXReconstruct captures Vulkan only"),
            std::string::npos)
      << named.dump();
  // Bounded: a capture past --capture-max-mb is stopped and not kept, said in its entry.
  const fs::path small = scratch("capture_cut");
  ASSERT_EQ(run(args + small.string() + " --capture failed --capture-max-mb 0.001").exit_code, 0);
  const auto cut = nlohmann::json::parse(omnishadow::bench::read_file((small / "captures.json").string()));
  ASSERT_EQ(cut["captures"].size(), 2u);
  const auto& vk = cut["captures"][1];
  EXPECT_EQ(vk["status"], "cut") << vk.dump();
  EXPECT_NE(vk["reason"].get<std::string>().find("grew past --capture-max-mb 0.001 MB"), std::string::npos)
      << vk.dump();
  EXPECT_FALSE(
      fs::exists(small / "captures" / "vulkan_room_c16_f32x24_six_pass_hard_linear_depth_d32f.gfxr"));
  const fs::path plain = scratch("capture_none");
  ASSERT_EQ(run(args + plain.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(plain / "captures.json")) << "--capture none (the default) captures nothing";
  EXPECT_FALSE(fs::exists(plain / "captures"));
}

// The capture layer is found where the loader finds it: in any folder of VK_LAYER_PATH, colon-separated (a
// carried install names its own folder; docs/gpu.md), and, when that is set, in none of the system's.
TEST_F(CliRun, CaptureLayerIsFoundWhereTheVulkanLoaderLooks) {
  std::string why;
  if (!vulkan_available(why)) GTEST_SKIP() << why;
  if (!fs::exists("/usr/share/vulkan/explicit_layer.d/VkLayer_gfxreconstruct.json"))
    GTEST_SKIP()
        << "GFXReconstruct is not installed (Debian package gfxreconstruct; scripts/setup.sh installs it)";
  const std::string vulkan_case =
      "run --backend vulkan --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames "
      "1 "
      "--warmup 0 --images none --benchmark_repetitions=1 --max-error 0.001 --capture failed --out ";
  for (const auto& [layer_path, status] :
       {std::pair<std::string, std::string>{"/nonexistent:/usr/share/vulkan/explicit_layer.d", "captured"},
        {"/nonexistent", "unsupported"}}) {
    const fs::path dir = scratch("capture_layer_path_" + status);
    setenv("VK_LAYER_PATH", layer_path.c_str(), 1);
    const Outcome found = run(vulkan_case + dir.string());
    unsetenv("VK_LAYER_PATH");
    ASSERT_EQ(found.exit_code, 0) << found.err;
    const auto listed = nlohmann::json::parse(omnishadow::bench::read_file((dir / "captures.json").string()));
    EXPECT_EQ(listed["captures"][0]["status"], status) << layer_path << ": " << listed.dump();
  }
}

// A folder a run is writing (its lock held: here by this test, as a run that has not yet written results.json
// would hold it) is refused at once, with and without isolation; once the lock is let go the run goes ahead.
TEST_F(CliRun, ASecondRunIntoTheSameOutIsRefusedWhileTheFirstHoldsIt) {
  const fs::path out = scratch("locked");
  fs::create_directories(out);
  const std::string args =
      "run --scene room --cube 16 --frame 32x24 --technique six_pass --filter hard --frames 1 --warmup 0 "
      "--no-accuracy --images none --benchmark_repetitions=1 --out " +
      out.string();
  {
    omnishadow::bench::FileLock held((out / ".omnishadow.lock").string());
    for (const char* isolation : {"process", "none"}) {
      const Outcome o = run(args + " --isolation " + isolation);
      EXPECT_EQ(o.exit_code, 2) << isolation << ": " << o.err;
      EXPECT_NE(o.err.find("--out " + out.string() + ": another run (pid " + std::to_string(::getpid()) +
                           ") is writing there"),
                std::string::npos)
          << o.err;
      EXPECT_FALSE(fs::exists(out / "results.json")) << isolation;
    }
  }
  const Outcome free = run(args);
  EXPECT_EQ(free.exit_code, 0) << free.err;
  EXPECT_TRUE(fs::exists(out / "results.json"));
}

// --isolation none runs in one process, as before: the first crash ends the run (here: none is injected).
TEST_F(CliRun, IsolationCanBeTurnedOff) {
  const FaultRun f = run_with_fault("no_isolation", "--isolation none");
  EXPECT_EQ(f.outcome.exit_code, 0) << f.outcome.err;
  EXPECT_FALSE(f.results["omnishadow"].contains("worker_processes"));
  const FaultRun bad = run_with_fault("bad_isolation", "--isolation threads");
  EXPECT_EQ(bad.outcome.exit_code, 2);
  EXPECT_NE(bad.outcome.err.find("--isolation"), std::string::npos) << bad.outcome.err;
}

}  // namespace omnishadow::cli_test
