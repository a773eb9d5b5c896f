// The omnishadow binary end to end: bad input gives one line naming the culprit and exit code 2; a small run
// writes results that Google Benchmark's compare.py reads; --check turns failed checks into exit code 1.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "bench/io/file_io.h"

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code;
  std::string out;
  std::string err;
};

fs::path scratch(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("omnishadow_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

Outcome run(const std::string& args) {
  fs::path base = scratch("io");
  fs::create_directories(base);
  std::string cmd = std::string(OMNISHADOW_BINARY) + " " + args + " >" + (base / "out").string() + " 2>" +
                    (base / "err").string();
  int status = std::system(cmd.c_str());
  Outcome o{WIFEXITED(status) ? WEXITSTATUS(status) : -1,
            omnishadow::bench::read_file((base / "out").string()),
            omnishadow::bench::read_file((base / "err").string())};
  return o;
}

// Skips only for the reason `list` gives ("gl: unavailable: ..."); a `list` that fails is a failure of the
// program, never a reason to skip (on the H100 it once exited 134 and every CLI test skipped itself).
// `omnishadow list` brings up both backends (a second or two under the sanitizers): once per process.
const Outcome& backends_listing() {
  static const Outcome listing = run("list");
  return listing;
}

bool gl_available(std::string& why) {
  const Outcome& o = backends_listing();
  EXPECT_EQ(o.exit_code, 0) << "omnishadow list failed:\n" << o.err;
  if (const size_t at = o.out.find("gl: unavailable"); at != std::string::npos) {
    why = "OpenGL backend unavailable here: " + o.out.substr(at, 200);
    return false;
  }
  return true;
}

bool vulkan_available(std::string& why) {
  const Outcome& o = backends_listing();
  if (const size_t at = o.out.find("vulkan: unavailable"); at != std::string::npos) {
    why = "Vulkan backend unavailable here: " + o.out.substr(at, 200);
    return false;
  }
  return true;
}

// Everything on stderr but the progress lines: what a user reads when the run refuses to start.
std::string error_lines(const std::string& err) {
  std::istringstream in(err);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("omnishadow: error: ", 0) == 0) out += line + "\n";
  return out;
}

struct BadInput {
  const char* args;
  const char* expected;  // substring of the single error line
};

class CliBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliBadInput, OneLineErrorAndExitCodeTwo) {
  std::string why;
  if (!gl_available(why)) GTEST_SKIP() << why;
  // Fixture files named @NAME@ in the arguments; each is written fresh for the case.
  const std::vector<std::pair<std::string, std::string>> fixtures = {
      {"BAD_SCENE", R"({"light": {}, "objects": [{"type": "box", "scale": -1}]})"},
      {"OVERFLOW_SCENE", R"({"light": {}, "objects": [{"type": "box", "translate": [0, 1e999, 0]}]})"},
      {"HUGE_SCENE", R"({"light": {}, "objects": [{"type": "box", "translate": [0, 0, 1e31]}]})"},
      {"EMPTY_SCENE", R"({"light": {}, "objects": []})"},
      {"TRUNCATED_SCENE", R"({"light": {}, "objects": [{"type": "bo)"},
      {"FOREIGN_RESULTS", R"({"context": {"date": "x"}, "benchmarks": []})"},
      {"TRUNCATED_RESULTS", R"({"omnishadow": {"format": "omnishadow-results/1", "cases": [{"id": )"},
      {"MISTYPED_RESULTS",
       R"({"omnishadow": {"format": "omnishadow-results/1", "cases": [{"id": "a", "images": 3}]}})"},
      {"EXISTING_FILE", "not a folder"}};
  std::string args = GetParam().args;
  for (const auto& [name, text] : fixtures) {
    std::string token = "@" + name + "@";
    size_t at = args.find(token);
    if (at == std::string::npos) continue;
    fs::path file = scratch(name + ".json");
    { std::ofstream(file) << text; }
    args.replace(at, token.size(), file.string());
  }
  if (size_t at = args.find("@EXISTING_RUN@"); at != std::string::npos) {
    fs::path dir = scratch("existing_run");
    fs::create_directories(dir);
    { std::ofstream(dir / "results.json") << "{}"; }
    args.replace(at, 14, dir.string());
  }
  // Files whose name or extension matters: a model cut short, and a scene named like a bundled one.
  if (size_t at = args.find("@TRUNCATED_GLB@"); at != std::string::npos) {
    fs::path file = scratch("truncated.glb");
    { std::ofstream(file) << std::string("glTF\x02\0\0\0\xff\xff\0\0", 12); }
    args.replace(at, 15, file.string());
  }
  if (size_t at = args.find("@OTHER_ROOM@"); at != std::string::npos) {
    fs::path dir = scratch("elsewhere");
    fs::create_directories(dir);
    { std::ofstream(dir / "room.json") << R"({"light": {}, "objects": [{"type": "box"}]})"; }
    args.replace(at, 12, (dir / "room.json").string());
  }
  // A run folder with an empty but valid results.json, for the commands that read one.
  for (size_t at; (at = args.find("@RUN@")) != std::string::npos;) {
    fs::path dir = scratch("a_run");
    fs::create_directories(dir);
    {
      std::ofstream(dir / "results.json")
          << R"({"omnishadow": {"format": "omnishadow-results/1", "cases": []}})";
    }
    args.replace(at, 5, dir.string());
  }
  if (size_t at = args.find("@OUT@"); at != std::string::npos) args.replace(at, 5, scratch("out").string());
  Outcome o = run(args);
  EXPECT_EQ(o.exit_code, 2) << o.err;
  std::string lines = error_lines(o.err);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 1) << o.err;
  EXPECT_NE(lines.find(GetParam().expected), std::string::npos)
      << "expected '" << GetParam().expected << "' in " << o.err;
}

INSTANTIATE_TEST_SUITE_P(
    Table, CliBadInput,
    ::testing::Values(
        BadInput{"run --technique teapot --out @OUT@", "--technique: unknown technique 'teapot'"},
        BadInput{"run --filter pcf9 --out @OUT@", "valid: hard, pcf_grid64, pcf_disk20, hw_compare2x2"},
        BadInput{"run --storage cubes --out @OUT@", "--storage: unknown storage"},
        BadInput{"run --cube 0 --out @OUT@", "--cube: '0' is not a valid size"},
        BadInput{"run --cube 1048576 --out @OUT@", "above the largest cube map"},
        // A value given twice, or two spellings of one case, would give two cases one id.
        BadInput{"run --scene room,room --out @OUT@", "--scene: a value is given twice ('room' and 'room')"},
        BadInput{"run --cube 64,064 --out @OUT@", "--cube: a value is given twice ('64' and '064')"},
        BadInput{"run --frame 64x48,64x48 --out @OUT@", "--frame: a value is given twice"},
        BadInput{"run --filter hard,pcss,hard --out @OUT@",
                 "--filter: a value is given twice ('hard' and 'hard')"},
        BadInput{"run --scene room --cube 16 --optimize cull+fit,fit+cull --out @OUT@",
                 "two values of one axis name the same case gl/room/c16"},
        BadInput{"run --frame 0x600 --out @OUT@", "--frame"},
        BadInput{"run --backend metal --out @OUT@", "unknown backend 'metal'"},
        BadInput{"run --scene @BAD_SCENE@ --out @OUT@", "BAD_SCENE.json: /objects/0/scale"},
        BadInput{"run --scene nosuchscene --out @OUT@", "nosuchscene.json: cannot open scene file"},
        BadInput{"run --scene room --out /proc/omnishadow", "--out /proc/omnishadow"},
        BadInput{"run --frobnicate", "frobnicate"}, BadInput{"run --shard 3/2 --out @OUT@", "--shard"},
        BadInput{"frobnicate",
                 "unknown command 'frobnicate' (commands: list, run, compare, merge, report, history, "
                 "alerts, accept, "
                 "threshold, store, fetch, export, device-key"},
        BadInput{"", "no command given (commands: list, run"},
        BadInput{"run --cube 16 --cube 32 --out @OUT@", "--cube is given 2 times: give it once"},
        BadInput{"run --out @OUT@ --benchmark_filter=nothing-matches-this", "empty"},
        BadInput{"run --out @OUT@ --benchmark_out=x.json", "--benchmark_out"},
        BadInput{"run --gl-profile es --out @OUT@", "--gl-profile: es not in {auto,core,compatibility}"},
        BadInput{"run --egl-platform wayland --out @OUT@",
                 "--egl-platform: wayland not in {surfaceless,device}"},
        BadInput{"run --egl-platform device --gl-device 99 --out @OUT@", "--gl-device 99"},
        BadInput{"run --backend vulkan --vk-device no-such-gpu --out @OUT@",
                 "--vk-device 'no-such-gpu' matches no Vulkan device"},
        BadInput{"run --backend vulkan --vk-device 7 --out @OUT@", "--vk-device 7 is out of range"},
        BadInput{"run --backend gl,vulkan --cube 40000 --out @OUT@", "above the largest cube map"},
        BadInput{"run --scene @OVERFLOW_SCENE@ --out @OUT@", "OVERFLOW_SCENE.json: malformed JSON"},
        BadInput{"run --scene @HUGE_SCENE@ --out @OUT@",
                 "HUGE_SCENE.json: /objects/0/translate/2: number must be finite and below 1e30"},
        BadInput{"run --scene @EMPTY_SCENE@ --out @OUT@", "EMPTY_SCENE.json: /objects: a scene needs"},
        BadInput{"run --scene @TRUNCATED_SCENE@ --out @OUT@", "TRUNCATED_SCENE.json: malformed JSON"},
        BadInput{"run --scene room --out @EXISTING_FILE@", "exists and is not a folder"},
        BadInput{"run --scene room --out @EXISTING_RUN@", "already holds a run (results.json)"},
        BadInput{"run --frame 640x0 --out @OUT@", "--frame"},
        BadInput{"compare @FOREIGN_RESULTS@ @FOREIGN_RESULTS@", "not an omnishadow results file"},
        BadInput{"compare @TRUNCATED_RESULTS@ @TRUNCATED_RESULTS@", "not valid JSON (truncated or corrupt)"},
        BadInput{"compare @MISTYPED_RESULTS@ @MISTYPED_RESULTS@",
                 "MISTYPED_RESULTS.json: /omnishadow/cases/0/images: expected an object"},
        BadInput{"merge @OUT@ @FOREIGN_RESULTS@", "not an omnishadow results file"},
        BadInput{"compare --alpha 2 @FOREIGN_RESULTS@ @FOREIGN_RESULTS@", "--alpha"},
        BadInput{"run --pcf-scale -1 --out @OUT@", "--pcf-scale: '-1' is not a scale"},
        BadInput{"run --remedy bias0+slope_bias --out @OUT@", "--remedy: bias0 and slope_bias exclude"},
        BadInput{"run --optimize cull+warp --out @OUT@", "--optimize: unknown optimisation 'warp'"},
        BadInput{"run --layout octahedral --out @OUT@", "--layout: unknown layout 'octahedral'"},
        BadInput{"run --tessellate 0 --out @OUT@", "--tessellate: '0' is not a valid"},
        BadInput{"run --tessellate 2,x --out @OUT@", "--tessellate: 'x' is not a valid"},
        BadInput{"run --tessellate 65 --out @OUT@", "--tessellate: 65 is more than 64 a side"},
        BadInput{"run --moments-tuning lbr0.4+blur9 --out @OUT@",
                 "--moments-tuning: unknown moments tuning 'blur9'"},
        BadInput{"run --moments-tuning exp3 --out @OUT@", "--moments-tuning: moments tuning 'exp3'"},
        BadInput{"run --precision 2 --sustain 5 --out @OUT@", "--precision and --sustain: choose one"},
        BadInput{"run --precision 0 --out @OUT@", "--precision"},
        BadInput{"run --precision 2 --precision-metric vram --out @OUT@", "--precision-metric"},
        BadInput{"run --out @OUT@ --benchmark_repetitions=zero", "--benchmark_repetitions: expected"},
        BadInput{"run --scene /nonexistent/model.glb --out @OUT@", "model.glb: cannot open model"},
        BadInput{"run --scene @TRUNCATED_GLB@ --out @OUT@", "truncated.glb: "},
        BadInput{"run --scene room,@OTHER_ROOM@ --out @OUT@", "would both be named 'room' in case ids"},
        BadInput{"run --light 1,2 --out @OUT@", "--light: expected X,Y,Z or X,Y,Z,AX,AY,AZ, got 2"},
        BadInput{"run --camera 1,nan,3 --out @OUT@", "--camera: 'nan' is not a finite number"},
        BadInput{"run --scene spot --light 0,1,0 --out @OUT@", "spot.json: --light moves the point light"},
        // Every option that takes a value, given one it cannot take (tests/bad_input_coverage_test.py holds
        // the table to that): the option named, and what it expected.
        BadInput{"run --scenes-dir /nonexistent --out @OUT@", "--scenes-dir /nonexistent: no such folder"},
        BadInput{"run --technique warp --out @OUT@", "--technique: unknown technique 'warp'"},
        BadInput{"run --depth-format d8 --out @OUT@", "--depth-format: unknown depth format 'd8'"},
        BadInput{"run --light-count 0 --out @OUT@", "--light-count: '0' is not a valid light count"},
        BadInput{"run --light-count 2000 --out @OUT@", "--light-count: 2000 is more than 1024 lights"},
        BadInput{"run --light-grouping per_face --out @OUT@",
                 "--light-grouping: unknown light grouping 'per_face'"},
        BadInput{"run --atlas-tiles by_area --out @OUT@", "--atlas-tiles: unknown atlas tiling 'by_area'"},
        BadInput{"run --shadow-budget 4G --out @OUT@", "--shadow-budget: '4G' is not a texel count"},
        BadInput{"run --shadow-budget 0MiB --out @OUT@",
                 "--shadow-budget: '0MiB': a budget in bytes must be"},
        BadInput{"run --update-budget 0 --out @OUT@", "--update-budget: '0' is not a face count"},
        BadInput{"run --staleness-frames -1 --out @OUT@",
                 "--staleness-frames: Value -1 not in range 0 to 10000"},
        BadInput{"run --isolation thread --out @OUT@", "--isolation: 'thread' is not process or none"},
        BadInput{"run --case-timeout-s nan --out @OUT@", "--case-timeout-s: 'nan' is not a finite number"},
        BadInput{"run --capture-max-mb 0 --out @OUT@", "--capture-max-mb"},
        BadInput{"run --capture-tool apitrace --out @OUT@", "--capture-tool: apitrace not in"},
        BadInput{"run --inject-crash '(' --out @OUT@", "--inject-crash: '(' is not a regular expression"},
        BadInput{"run --inject-hang [ --out @OUT@", "--inject-hang: '[' is not a regular expression"},
        BadInput{"run --capture sometimes --out @OUT@",
                 "--capture: sometimes not in {failed,crashed,all,none}"},
        BadInput{"run --inject-in nowhere --out @OUT@", "--inject-in: 'nowhere' is not checks or timed"},
        BadInput{"run --frames 0 --out @OUT@", "--frames: Value 0 not in range 1 to 1000000"},
        BadInput{"run --warmup -1 --out @OUT@", "--warmup: Value -1 not in range"},
        BadInput{"run --warmup-ms nan --out @OUT@", "--warmup-ms: 'nan' is not a finite number"},
        BadInput{"run --repetition-ms inf --out @OUT@", "--repetition-ms: 'inf' is not a finite number"},
        BadInput{"run --inject-frame-ms -1 --out @OUT@", "--inject-frame-ms: Value -1 not in range"},
        BadInput{"run --settle-s 1e9 --out @OUT@", "--settle-s: Value 1e9 not in range 0 to 600"},
        BadInput{"run --check-frame -1 --out @OUT@", "--check-frame: Value -1 not in range"},
        BadInput{"run --face-tolerance -1 --out @OUT@", "--face-tolerance: Value -1 not in range"},
        BadInput{"run --lit-tolerance nan --out @OUT@", "--lit-tolerance: 'nan' is not a finite number"},
        BadInput{"run --cross-lit-tolerance 256 --out @OUT@",
                 "--cross-lit-tolerance: Value 256 not in range"},
        BadInput{"run --cross-shadow-tolerance 2 --out @OUT@",
                 "--cross-shadow-tolerance: Value 2 not in range"},
        BadInput{"run --cross-max-percent 101 --out @OUT@", "--cross-max-percent: Value 101 not in range"},
        BadInput{"run --light-radius -1 --out @OUT@", "--light-radius: Value -1 not in range"},
        BadInput{"run --light-samples 0 --out @OUT@", "--light-samples: Value 0 not in range 1 to 64"},
        BadInput{"run --sphere-stride -1 --out @OUT@", "--sphere-stride: Value -1 not in range 0 to 64"},
        BadInput{"run --max-error 1e3 --out @OUT@", "--max-error: Value 1e3 not in range 0 to 100"},
        BadInput{"run --inject-fragment-work x --out @OUT@",
                 "--inject-fragment-work: 'x' is not a whole number from 0 to 1000000"},
        BadInput{"run --replicas 0 --out @OUT@", "--replicas: Value 0 not in range 1 to 16"},
        BadInput{"run --raster-perturb nan --out @OUT@", "--raster-perturb: 'nan' is not a finite number"},
        BadInput{"run --lookup-perturb 5 --out @OUT@", "--lookup-perturb: Value 5 not in range 0 to 4"},
        BadInput{"run --memory-budget lots --out @OUT@", "--memory-budget: lots unit not recognized"},
        BadInput{"run --images some --out @OUT@", "--images: some not in {failed,all,none}"},
        BadInput{"run --cube-read-back half --out @OUT@",
                 "--cube-read-back: half not in {auto,full,sampled}"},
        BadInput{"run --max-repetitions 0 --out @OUT@", "--max-repetitions: Value 0 not in range"},
        BadInput{"run --sustain 0 --out @OUT@", "--sustain: Value 0 not in range"},
        BadInput{"run --gl-device x --egl-platform device --out @OUT@",
                 "--gl-device: expects an EGL device index (0, 1, ...), got 'x'"},
        BadInput{"compare --min-effect nan @FOREIGN_RESULTS@ @FOREIGN_RESULTS@",
                 "--min-effect: 'nan' is not a finite number"},
        BadInput{"compare --metric vram @FOREIGN_RESULTS@ @FOREIGN_RESULTS@", "--metric: vram not in"},
        BadInput{"compare --gate /nonexistent/gate.json @RUN@ @RUN@", "gate file /nonexistent/gate.json"},
        BadInput{"compare --out /proc/omnishadow @RUN@ @RUN@",
                 "compare --out /proc/omnishadow: cannot create"},
        BadInput{"merge /proc/omnishadow @RUN@", "merge OUT /proc/omnishadow: cannot create the folder"},
        BadInput{"merge @OUT@ /nonexistent/run", "/nonexistent/run: cannot read"},
        BadInput{"report /nonexistent/run", "report: /nonexistent/run is no run"},
        BadInput{"store /nonexistent/run --db sqlite:@OUT@/store.db", "store: /nonexistent/run: cannot read"},
        BadInput{"export /nonexistent/run --format bencher", "export: /nonexistent/run: cannot read"},
        BadInput{"export @RUN@ --format csv",
                 "export: --format: 'csv' is not bencher or github-action-benchmark"},
        BadInput{"export @RUN@ --format bencher --out /proc/omnishadow/x.json", "/proc/omnishadow/x.json"},
        BadInput{"store @RUN@ --db mysql://localhost/runs", "--db mysql://localhost/runs: not sqlite:PATH"},
        BadInput{"store @RUN@ --db sqlite:@OUT@/s.db?timeout=soon",
                 "timeout=soon is not a whole number of seconds"},
        BadInput{"store @RUN@ --db postgresql://fleet:s3cret@127.0.0.1:1/runs",
                 "--db postgresql://fleet:***@127.0.0.1:1/runs: cannot open: "},
        BadInput{"report @RUN@ --history /nonexistent/h", "report --history /nonexistent/h: no such run"},
        BadInput{"report @RUN@ --out /proc/omnishadow/r.html", "--out /proc/omnishadow/r.html"},
        BadInput{"report @RUN@ --db mysql://localhost/runs", "--db mysql://localhost/runs: not sqlite:PATH"},
        BadInput{"history", "history: give run folders (or folders of runs) or --db URL"},
        BadInput{"history /nonexistent/h", "history: /nonexistent/h: no such run or folder"},
        BadInput{"history --db sqlite:@OUT@/empty.db", "/empty.db: no runs stored"},
        BadInput{"history @RUN@ --out /proc/omnishadow/h", "/proc/omnishadow/h"},
        BadInput{"history @RUN@ --device-key nothing-like-it", "nothing-like-it"},
        BadInput{"history @RUN@ --accepted @TRUNCATED_RESULTS@", "--accepted "},
        BadInput{"fetch --db mysql://localhost/runs --out @OUT@/f",
                 "--db mysql://localhost/runs: not sqlite:PATH"},
        BadInput{"alerts --db sqlite:@OUT@/empty.db", "alerts --db sqlite:"},
        BadInput{"alerts --db mysql://localhost/runs", "--db mysql://localhost/runs: not sqlite:PATH"},
        BadInput{"alerts --db sqlite:@OUT@/e.db --out", "--out: 1 required"},
        BadInput{"alerts --db sqlite:@OUT@/e.db --device-key", "--device-key: 1 required"},
        BadInput{"accept --db sqlite:@OUT@/s.db --case [ --metric m --commit c --reason r",
                 "accept: --case: '[' is not a regular expression"},
        BadInput{"accept --db mysql://x --case c --metric m --commit c --reason r", "not sqlite:PATH"},
        BadInput{"accept --db sqlite:@OUT@/s.db --case c --metric '(' --commit c --reason r",
                 "--metric: '('"},
        BadInput{"accept --db sqlite:@OUT@/s.db --case c --metric m --commit c", "--reason is required"},
        BadInput{"accept --db sqlite:@OUT@/s.db --case c --metric m --reason r --commit",
                 "--commit: 1 required"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --metric frame_ms --percent nan",
                 "--percent: 'nan' is not a finite"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --metric frame_ms --alpha 2 --min-effect 0.1",
                 "--alpha: Value 2 not in range"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --metric frame_ms --alpha 0.1 --min-effect -1",
                 "--min-effect: Value -1 not in range"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --metric frame_ms --alpha 0.1",
                 "threshold: --alpha and --min-effect go together"},
        BadInput{
            "threshold --db sqlite:@OUT@/s.db --metric frame_ms --percent 5 --alpha 0.1 --min-effect 0.1",
            "give --percent P, or --alpha A with --min-effect E, not both or neither"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --metric [ --percent 5", "--metric: '[' is not a regular"},
        BadInput{"threshold --db mysql://x --metric m --percent 5", "not sqlite:PATH"},
        BadInput{"threshold --db sqlite:@OUT@/s.db --device '(' --metric m --percent 5", "--device: '('"},
        BadInput{"fetch --out @RUN@", "/a_run: exists and is not an empty folder"},
        BadInput{"fetch --out @OUT@/f --commit", "--commit: 1 required"},
        BadInput{"fetch --db sqlite:@OUT@/s.db --out @OUT@/f --device-key", "--device-key: 1 required"},
        BadInput{"list --scenes-dir /nonexistent", "--scenes-dir /nonexistent: no such folder"},
        BadInput{"list --egl-platform wayland", "--egl-platform: wayland not in {surfaceless,device}"},
        BadInput{"list --gl-profile es", "--gl-profile: es not in {auto,core,compatibility}"},
        BadInput{"list --gl-device x --egl-platform device", "--gl-device: expects an EGL device index"},
        BadInput{"list --vk-device", "--vk-device: 1 required TEXT missing"},
        BadInput{"list --api-checks=maybe", "--api-checks"}),
    [](const ::testing::TestParamInfo<BadInput>& info) { return "case" + std::to_string(info.index); });

class CliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!gl_available(why)) GTEST_SKIP() << why;
  }
};

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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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

// Rounds until the time is up; every case then holds its stability figure and its clock samples per
// repetition.
TEST_F(CliRun, SustainLoopsRoundsAndReportsStability) {
  fs::path out = scratch("sustain");
  Outcome o =
      run("run --scene room --cube 32 --frame 64x48 --technique six_pass,geometry_shader --filter hard "
          "--frames 2 --warmup 0 --no-accuracy --no-images --sustain 2 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto k = nlohmann::json::parse(omnishadow::bench::read_file((named / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto k = nlohmann::json::parse(omnishadow::bench::read_file((asked / "results.json").string()));
  EXPECT_EQ(k["omnishadow"]["cases"].size(), 2u);
}

// The GPU-specific single passes, asked for by name with --check on both APIs, beside six_pass with
// culling on and off. A device without their extensions (Mesa's CPU drivers) reports each case unsupported
// with the missing extension named, and the matrix goes on; a device with them (an NVIDIA GPU) must pass
// every check. nv_swizzle refuses hardware_depth on every device, with its reason.
TEST_F(CliRun, NvSwizzleAndMeshShaderRunWithChecksOrSayWhichExtensionIsMissing) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("singlepass");
  Outcome o =
      run("run --backend " + backends +
          " --scene room --cube 64 --frame 160x120"
          " --technique six_pass,nv_swizzle,mesh_shader --filter hard,pcf_disk20"
          " --storage linear_depth,r32f_distance,hardware_depth --optimize none,cull --frames 1 --warmup 0"
          " --images none --check --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int six_pass_ok = 0, gpu_paths = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    const std::string id = c["id"], technique = c["axes"]["technique"], status = c["status"];
    if (c["axes"]["filter"] == "pcf_disk20" && c["axes"]["storage"] != "linear_depth")
      continue;  // not read so
    if (technique == "six_pass") {
      six_pass_ok += status == "ok";
      continue;
    }
    ++gpu_paths;
    if (status == "ok") continue;  // with --check: every check passed
    ASSERT_EQ(status, "unsupported") << c.dump();
    const std::string reason = c["reason"];
    // An NVIDIA driver offers every extension these need (gpu/measured: H100, driver 580): there the only
    // case that may be unsupported is nv_swizzle's refused hardware_depth, so a broken extension probe fails
    // here.
    const std::string renderer =
        j["omnishadow"]["devices"][c["axes"]["backend"].get<std::string>()]["renderer"];
    if (renderer.find("NVIDIA") != std::string::npos) {
      EXPECT_TRUE(technique == "nv_swizzle" && c["axes"]["storage"] == "hardware_depth")
          << id << " is unsupported on " << renderer << ": " << reason;
    }
    if (technique == "nv_swizzle" && c["axes"]["storage"] == "hardware_depth") {
      EXPECT_NE(reason.find("hardware_depth"), std::string::npos) << reason;
    } else if (technique == "nv_swizzle") {
      EXPECT_NE(reason.find("NV_viewport_swizzle"), std::string::npos) << reason;
    } else {
      EXPECT_NE(reason.find(id.rfind("gl/", 0) == 0 ? "GL_NV_mesh_shader" : "VK_EXT_mesh_shader"),
                std::string::npos)
          << reason;
    }
  }
  EXPECT_GT(six_pass_ok, 0) << "the matrix went on past the unsupported cases";
  EXPECT_GT(gpu_paths, 0);
}

// nv_swizzle's emulation (--emulate-nv-swizzle: an ordinary GS applies each face's swizzle) runs everything
// of nv_swizzle but the NV extensions on the CPU drivers: its vertex stage, the swizzle table as the GPU
// applies it, the viewport mask with culling, the reversed depth test and clear of r32f_distance. Every check
// against six_pass and exact visibility must pass on both APIs (heavy at cube 64 is past the default error
// limit for six_pass too:
// --max-error 100; a flipped culling sign or an unreversed depth test fails the checks:
// docs/mutants.md).
TEST_F(CliRun, EmulatedNvSwizzlePassesEveryCheckOnBothApis) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("swizzle_emulated");
  Outcome o = run(
      "run --backend " + backends +
      " --scene room,heavy --cube 64 --frame 160x120"
      " --technique six_pass,nv_swizzle --filter hard --storage linear_depth,r32f_distance"
      " --optimize none,cull --emulate-nv-swizzle --frames 1 --warmup 0 --images none --check --max-error 100"
      " --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int emulated = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump();
    const std::string id = c["id"];
    if (c["axes"]["technique"] == "nv_swizzle") {
      EXPECT_EQ(id.substr(id.size() - 9), "/emulated") << id;
      ++emulated;
    }
  }
  EXPECT_EQ(emulated, (backends == "gl" ? 1 : 2) * 2 * 2 * 2) << "backends x scenes x storages x culling";
}

// The face_array layout runs with --check on both APIs (truth, timing, the technique checks within
// the layout), beside the cube; its cases carry the layout in the id and the JSON axes.
TEST_F(CliRun, FaceArrayLayoutPassesItsChecksBesideTheCube) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("layouts");
  Outcome o =
      run("run --backend " + backends +
          " --scene room --cube 128 --frame 400x300 --layout cube,face_array"
          " --technique six_pass,geometry_shader --filter hard,pcf_disk20,hw_compare2x2,vsm --frames 1"
          " --warmup 0 --images none --check --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int face_array_ok = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    const std::string id = c["id"];
    const bool face_array = id.find("/face_array") != std::string::npos;
    EXPECT_EQ(c["axes"]["layout"], face_array ? "face_array" : "cube") << id;
    if (c["status"] == "unsupported") continue;  // lavapipe's D32F has no linear filtering (hw_compare2x2)
    EXPECT_EQ(c["status"], "ok") << c.dump();
    if (!face_array || c["status"] != "ok") continue;
    ++face_array_ok;
    EXPECT_TRUE(c["accuracy"].contains("misclassified_percent")) << id;
  }
  EXPECT_GE(face_array_ok, backends == "gl,vulkan" ? 14 : 8);
}

// dual_paraboloid passes its checks on both APIs: its techniques agree with its six_pass, its
// texels are a figure (the warp bends edges), and against exact visibility its error falls with tessellation
// to the cube's. The techniques it has no pass for yet are unsupported with the reason.
TEST_F(CliRun, DualParaboloidPassesItsChecksAndTessellationBringsItToTheCube) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("paraboloid");
  Outcome o = run(
      "run --backend " + backends +
      " --scene mixed --cube 128 --frame 400x300 --layout cube,dual_paraboloid"
      " --tessellate 1,8 --technique six_pass,geometry_shader,vs_layer --filter hard,pcf_disk20 --frames 1"
      " --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  std::map<std::string, double> misclassified;  // backend/layout/tessellation, six_pass hard
  int paraboloid_ok = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    const std::string id = c["id"];
    const bool paraboloid = c["axes"]["layout"] == "dual_paraboloid";
    if (paraboloid && c["axes"]["technique"] == "vs_layer") {
      EXPECT_EQ(c["status"], "unsupported") << id;
      EXPECT_NE(c["reason"].get<std::string>().find("dual_paraboloid is drawn by six_pass"),
                std::string::npos)
          << id;
      continue;
    }
    if (c["status"] == "unsupported") continue;  // vs_layer where the device lacks it
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    paraboloid_ok += paraboloid;
    if (c["axes"]["technique"] == "six_pass" && c["axes"]["filter"] == "hard")
      misclassified[c["axes"]["backend"].get<std::string>() + "/" + c["axes"]["layout"].get<std::string>() +
                    "/" + std::to_string(c["axes"]["tessellation"].get<int>())] =
          c["accuracy"]["misclassified_percent"];
  }
  EXPECT_GE(paraboloid_ok, backends == "gl,vulkan" ? 16 : 8);
  for (const std::string api : {"gl", "vulkan"}) {
    if (!misclassified.count(api + "/cube/1")) continue;
    const double cube = misclassified[api + "/cube/1"], coarse = misclassified[api + "/dual_paraboloid/1"],
                 fine = misclassified[api + "/dual_paraboloid/8"];
    EXPECT_NEAR(misclassified[api + "/cube/8"], cube, 0.05) << "tessellation leaves the cube's figure";
    EXPECT_GT(coarse, 5.0 * fine)
        << "mixed's floor is two triangles: straight edges where the paraboloid curves";
    EXPECT_NEAR(fine, cube, 1.0) << "tessellated 8x, the paraboloid comes within a point of the cube";
  }
}
// tetrahedral: four perspective faces, so its texels are held to the exact ray-cast truth as the
// cube's are (cube_texels is a check here, not a figure), its techniques agree with its six_pass, and both
// APIs agree.
TEST_F(CliRun, TetrahedralPassesItsChecksAndItsExactTexelTruth) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("tetrahedral");
  // tetra_seams: casters on its faces' corners, edges and tie planes (the layouts' extremes).
  const std::string seams = std::string(OMNISHADOW_TEST_SCENES_DIR) + "/extremes/tetra_seams.json";
  Outcome o =
      run("run --backend " + backends + " --scene room,mixed," + seams +
          " --cube 128 --frame 400x300 --layout tetrahedral"
          " --technique six_pass,geometry_shader --filter hard,pcf_disk20 --frames 1 --warmup 0 --images none"
          " --check --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int ok = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["axes"]["layout"], "tetrahedral");
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    ok += c["status"] == "ok";
    if (c["axes"]["technique"] != "six_pass") continue;
    EXPECT_EQ(c["shadow_plan"]["texels"], 4 * 157 * 157) << "four faces of round(128 sqrt 1.5)";
    EXPECT_GT(c["cube_texels"]["texels"].get<int>(), 0);
    EXPECT_LE(c["cube_texels"]["bad_percent"].get<double>(), 0.1) << "the cube's limit";
  }
  EXPECT_EQ(ok, backends == "gl,vulkan" ? 24 : 12);
}

// Layout atlas: four hall lamps as tiles of one texture pass every check light by light (texels, lookups, the
// moments, the other API, six_pass within the atlas) on both APIs, per face and in one pass routed by
// viewport; each light's lookups read its own tiles (the lookup check replays them against the tiles read
// back) and vsm's blur stays in the light's tiles (the moments check). Cube 48: no power of two, the single
// pass's bound.
TEST_F(CliRun, AtlasPassesEveryCheckForEveryLightOnBothApis) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("atlas");
  Outcome o =
      run("run --backend " + backends +
          " --scene hall --light-count 1,4 --cube 48 --frame 200x150 --layout atlas"
          " --technique six_pass,geometry_shader,vs_layer --filter hard,pcf_disk20,vsm --frames 1 --warmup 0"
          " --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int ok = 0, lookups = 0, moments = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["axes"]["layout"], "atlas");
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    ok += c["status"] == "ok";
    if (c.contains("lookups") && c["lookups"].value("pixels", 0) > 0) ++lookups;
    if (c.contains("moments") && c["moments"].value("values", 0) > 0) ++moments;
  }
  EXPECT_EQ(ok, backends == "gl,vulkan" ? 36 : 18);
  EXPECT_GT(lookups, 0) << "the lookup check ran on atlas cases";
  EXPECT_GT(moments, 0) << "the moments check ran on atlas cases";
}

// Culled to the view from mid-hall and shaded from clustered lists: lamps behind the camera and faces turned
// away get no pass, which results.json counts, and every case still passes six_pass unculled and unclustered,
// its pixels' faces check and its clusters' check; with every light in one pass it is unsupported with its
// reason.
TEST_F(CliRun, ViewCullingCountsWhatItLeftOutAndPassesEveryCheck) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("view");
  Outcome o = run(
      "run --backend " + backends +
      " --scene hall --light-count 16 --camera 0,3,0,20,2,0 --optimize view+clusters --cube 16 --frame 96x64"
      " --technique six_pass,vs_layer --light-grouping per_light,all_lights --filter pcf_disk20"
      " --frames 1 --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int ok = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    if (c["status"] == "unsupported") {  // six_pass has no one pass at all; vs_layer's is not culled
      if (c["axes"]["technique"] != "vs_layer") continue;
      EXPECT_NE(c["reason"].get<std::string>().find("view culling with every light in one pass"),
                std::string::npos)
          << c["reason"];
      continue;
    }
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    ok += c["status"] == "ok";
    const auto& culled = c["shadow_plan"]["view_culling"];
    EXPECT_GT(culled["lights_culled"].get<int>(), 0) << c["id"];
    EXPECT_GT(culled["faces_culled"].get<int>(), 0) << c["id"];
    bool held_to_unculled = false;
    for (const auto& check : c["checks"])
      held_to_unculled |=
          check["name"] == "lit" && check["against"].get<std::string>().find("/view") == std::string::npos;
    EXPECT_TRUE(held_to_unculled) << c["id"] << ": its lit frame against six_pass unculled";
  }
  EXPECT_EQ(ok, backends == "gl,vulkan" ? 4 : 2);
  // Beside a lamp, inside its range: faces culled, not lights. The moments blur still runs over a face left
  // out (it holds an earlier frame's moments, blurred again): the moments check must not hold it to this
  // frame's.
  fs::path beside = scratch("view_beside_lamp");
  o = run(
      "run --backend " + backends +
      " --scene hall --light-count 16 --camera -30,5.2,-4.2,10,3,0 --optimize view --cube 32 --frame 96x64"
      " --technique six_pass --filter vsm --frames 1 --warmup 0 --images none --check --max-error 100"
      " --benchmark_repetitions=1 --out " +
      beside.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  j = nlohmann::json::parse(omnishadow::bench::read_file((beside / "results.json").string()));
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    EXPECT_GT(c["shadow_plan"]["view_culling"]["faces_culled"].get<int>(), 0) << c["id"];
    EXPECT_GT(c["moments"]["values"].get<int>(), 0) << c["id"] << ": the moments check ran";
  }
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

// An update budget on both APIs: the check frame's maps are whole (every check holds), and the sequence from
// a fresh start renders at most the budget's faces a frame after the first, every face read within its wait
// bound; the stale faces of the swaying lamps and of those the moving casters reach cost misclassified
// pixels.
TEST_F(CliRun, UpdateBudgetRendersAtMostItsFacesAndReportsWhatStalenessCosts) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("update_budget");
  Outcome o = run("run --backend " + backends +
                  " --scene hall --light-count 8 --update-budget none,2,12 --staleness-frames 12 --cube 32"
                  " --frame 96x64 --technique six_pass,geometry_shader --filter hard --frames 1 --warmup 0"
                  " --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
                  out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int sequences = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    const int budget = c["axes"]["update_budget_faces"].get<int>();
    if (c["status"] == "unsupported") {  // geometry_shader refreshes whole lights: 2 faces are too few
      EXPECT_EQ(c["axes"]["technique"], "geometry_shader");
      EXPECT_EQ(budget, 2);
      EXPECT_NE(c["reason"].get<std::string>().find("the budget must be at least 6"), std::string::npos);
      continue;
    }
    ASSERT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    const auto& s = c["staleness"];
    ASSERT_EQ(s["frames"].size(), 12u) << c["id"];
    ++sequences;
    EXPECT_EQ(s["lights"], nlohmann::json({0, 2, 3, 4, 6, 7})) << "checked (0, 2, 4, 6) and swaying (3, 7)";
    EXPECT_EQ(s["frames"][0]["faces_rendered"], 48) << "the first frame renders every light whole";
    for (size_t t = 1; t < s["frames"].size(); ++t) {
      const int rendered = s["frames"][t]["faces_rendered"].get<int>();
      if (budget > 0) {
        EXPECT_LE(rendered, budget) << c["id"] << " frame " << t;
      } else {
        EXPECT_EQ(rendered, 48) << "no budget: every light every frame";
      }
    }
    if (budget == 2) {  // two lamps sway: 12 stale faces a frame, 2 refreshed
      EXPECT_GT(s["max_wait_frames"].get<int>(), 0);
      EXPECT_GT(s["misclassified_percent"]["worst"].get<double>(), 0.0) << c["id"];
    }
    if (budget == 12) {  // the swaying lamps' 12 faces and those the rollers and carts reach: more than 12
      EXPECT_GT(s["wait_bound_frames"].get<int>(), 0) << c["id"];
      EXPECT_LE(s["max_wait_frames"].get<int>(), s["wait_bound_frames"].get<int>()) << c["id"];
    }
  }
  EXPECT_EQ(sequences, backends == "gl,vulkan" ? 10 : 5);
  // Without the exact reference the sequence still holds the faces to the paths, and claims no error.
  fs::path plain = scratch("update_budget_no_accuracy");
  o =
      run("run --backend gl --scene hall --light-count 8 --update-budget 2 --staleness-frames 6 --cube 16"
          " --frame 64x48 --technique six_pass --filter hard --frames 1 --warmup 0 --images none --check"
          " --no-accuracy --benchmark_repetitions=1 --out " +
          plain.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  j = nlohmann::json::parse(omnishadow::bench::read_file((plain / "results.json").string()));
  const auto& s = j["omnishadow"]["cases"][0]["staleness"];
  EXPECT_TRUE(s["misclassified_percent"].is_null()) << s.dump();
  EXPECT_TRUE(s["frames"][5]["misclassified_percent"].is_null());
  EXPECT_GT(s["max_wait_frames"].get<int>(), 0);
}

// The hall's rollers and carts move: at a frame far from the one the scene was loaded at, every technique
// draws them where that frame has them on both APIs (texels, lookups and exact visibility of each light held
// to the scene posed there, the APIs and techniques to each other), with the static cache too (a sequence of
// frames from a fresh start: each lamp a moving caster reaches renders again, no face read stale);
// mesh_shader too (through its emulation), whose moving meshlets' spheres follow the casters every frame.
TEST_F(CliRun, MovingCastersAreDrawnWhereTheirFrameHasThem) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("moving_casters");
  Outcome o =
      run("run --backend " + backends +
          " --scene hall --light-count 4 --check-frame 90 --optimize none,cache --staleness-frames 4"
          " --cube 64 --frame 200x150"
          " --technique six_pass,geometry_shader,vs_layer,mesh_shader --emulate-mesh-shader --filter hard"
          " --frames 2 --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  int checked = 0, meshes = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    if (c["status"] == "unsupported")
      continue;  // vs_layer, and mesh_shader's emulation, where the driver lacks it
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    ++checked;
    meshes += c["axes"]["technique"] == "mesh_shader";
  }
  EXPECT_GE(checked, backends == "gl,vulkan" ? 8 : 4);
  EXPECT_GT(meshes, 0) << "mesh_shader's emulation ran nowhere";
}

// A model file (glTF or OBJ) given to --scene runs directly and passes its checks on both APIs, named by
// its file stem; the loader's time is in the results and the summary.
TEST_F(CliRun, ModelFilesRunDirectlyAndPassTheirChecksOnBothApis) {
  const std::string engine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
  if (!fs::exists(engine) || !fs::exists(bunny))
    GTEST_SKIP() << engine << " or " << bunny
                 << " missing: bash scripts/setup.sh installs assimp-testmodels and glmark2-data";
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  fs::path out = scratch("models");
  Outcome o = run(
      "run --backend " + backends + " --scene " + engine + "," + bunny +
      " --cube 256 --frame 400x300 --technique six_pass,geometry_shader --filter hard,pcf_disk20 --frames 1"
      " --warmup 0 --images none --check --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto k = nlohmann::json::parse(omnishadow::bench::read_file((hand / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((merged / "results.json").string()));
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
  auto p = nlohmann::json::parse(omnishadow::bench::read_file((partial / "results.json").string()));
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
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
    auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
    auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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

namespace {

// SIGINT mid-matrix: the run stops after the case in hand, exits 130 and leaves valid JSON with what
// finished.
TEST_F(CliRun, InterruptedRunLeavesValidResults) {
  fs::path out = scratch("interrupted");
  fs::path log = scratch("interrupted.log");
  std::string cmd = std::string(OMNISHADOW_BINARY) + " run --scene room,ogldev --cube 16,32,64,128,256,512 " +
                    "--frames 50 --light-radius 0 --no-images --out " + out.string() + " 2>" + log.string();
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until at least one case is saved, then interrupt: however long that takes on this machine (ctest's
  // timeout bounds it), unless the run ends first.
  fs::path results = out / "results.json";
  int status = 0;
  bool ended = false;
  while (!fs::exists(results) && !(ended = waitpid(pid, &status, WNOHANG) == pid)) usleep(50 * 1000);
  ASSERT_FALSE(ended) << "the run ended before saving a case: " << omnishadow::bench::read_file(log.string());
  kill(pid, SIGINT);
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the run must exit, not die by the signal";
  EXPECT_EQ(WEXITSTATUS(status), 130) << omnishadow::bench::read_file(log.string());
  auto j = nlohmann::json::parse(omnishadow::bench::read_file(results.string()));  // valid JSON, whole
  EXPECT_FALSE(j["omnishadow"]["complete"].get<bool>());
  EXPECT_EQ(j["omnishadow"]["stopped_by"], "SIGINT");
  size_t cases = j["omnishadow"]["cases"].size();
  EXPECT_GE(cases, 1u);
  EXPECT_LE(cases, 2u * 6u * 5u * 3u);
  EXPECT_NE(omnishadow::bench::read_file(log.string()).find("stopped by SIGINT"), std::string::npos);
  // The summary says so first. Stopped during the untimed checks (180 checked cases take minutes here): no
  // case was timed, so none is ok.
  const std::string summary = omnishadow::bench::read_file((out / "summary.md").string());
  EXPECT_EQ(summary.rfind("**Incomplete run: stopped by SIGINT during the ", 0), 0u) << summary;
  const bool untimed = summary.rfind("**Incomplete run: stopped by SIGINT during the untimed checks", 0) == 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    ASSERT_TRUE(c.contains("status")) << c.dump();
    if (untimed) {
      EXPECT_NE(c["status"], "ok") << c["id"] << ": never timed";
    }
  }
}

// SIGTERM in the middle of a timed round: the run exits 143 with valid results that say so, the cases the
// round had not reached marked interrupted. That it stops after the repetition in hand, not after the round,
// is HarnessTest.StopEndsTheRunAfterTheRepetitionInHand's, counted in the scripted device's frames, not in
// seconds.
TEST_F(CliRun, SigtermInsideARoundLeavesValidResults) {
  fs::path out = scratch("prompt_stop");
  fs::path log = scratch("prompt_stop.log");
  std::string cmd =
      std::string(OMNISHADOW_BINARY) +
      " run --backend gl --scene room --cube 128 --frame 400x300 --technique six_pass,geometry_shader,"
      "vs_layer --filter hard,pcf_grid64,pcf_disk20 --storage linear_depth,r32f_distance,hardware_depth "
      "--frames 200 --warmup 0 --no-accuracy --no-images --benchmark_repetitions=2 --out " +
      out.string() + " 2>" + log.string();
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  auto log_text = [&] {
    std::ifstream f(log);
    std::stringstream text;
    text << f.rdbuf();
    return text.str();
  };
  // Wait until the third repetition of round 1 has started, however long that takes here, unless the run
  // ends.
  int status = 0;
  bool ended = false;
  while (log_text().find("[time round 1/2, 3/") == std::string::npos &&
         !(ended = waitpid(pid, &status, WNOHANG) == pid))
    usleep(50 * 1000);
  ASSERT_FALSE(ended) << "the run ended before round 1's third case: " << log_text();
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  EXPECT_FALSE(j["omnishadow"]["complete"].get<bool>());
  EXPECT_EQ(j["omnishadow"]["stopped_by"], "SIGTERM");
  int timed = 0, interrupted = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    if (c["status"] == "interrupted") ++interrupted;
    if (c.contains("timing") && c["timing"]["repetitions"].get<int>() > 0) ++timed;
  }
  EXPECT_GE(timed, 2) << "round 1's first two cases were timed";
  EXPECT_GT(interrupted, 0) << "the round was cut short, not finished";
  EXPECT_NE(log_text().find("stopped by SIGTERM"), std::string::npos) << log_text();
}

// The run of `--cube 16384,64` in `out`: the first case a resource_error (a memory finding), the second ok.
// Returns the first case's reason ("" when the file does not hold two cases; the failures are recorded).
std::string out_of_memory_then_ok(const fs::path& out) {
  auto j = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  const auto& cases = j["omnishadow"]["cases"];
  EXPECT_EQ(cases.size(), 2u);
  if (cases.size() != 2) return "";
  EXPECT_EQ(cases[0]["status"], "resource_error");
  EXPECT_EQ(cases[0]["findings"][0]["check"], "memory");
  EXPECT_EQ(cases[1]["status"], "ok") << cases[1].dump();
  return cases[0].value("reason", "");
}

// Out of memory is a result, never a crash, and the matrix goes on. Predicted (bench/run/memory_budget.h):
// with
// --memory-budget the 16384 cube (about 13 GiB of targets) cannot fit in 1 GiB on any device, so it fails
// before allocating, and the 64 cube after it runs.
TEST_F(CliRun, PredictedOutOfMemoryFailsTheCaseAndTheMatrixGoesOn) {
  bool vulkan = run("list").out.find("vulkan: unavailable") == std::string::npos;
  for (std::string backend : {"gl", "vulkan"}) {
    if (backend == "vulkan" && !vulkan) continue;
    SCOPED_TRACE(backend);
    fs::path out = scratch("oom_predicted_" + backend);
    Outcome o =
        run("run --backend " + backend +
            " --scene room --cube 16384,64 --technique six_pass --filter hard "
            "--frames 1 --warmup 0 --no-images --no-accuracy --benchmark_repetitions=1 --memory-budget 1G "
            "--out " +
            out.string());
    EXPECT_EQ(o.exit_code, 0) << o.out;
    const std::string reason = out_of_memory_then_ok(out);
    EXPECT_NE(reason.find("out of memory (predicted)"), std::string::npos) << reason;
    EXPECT_NE(reason.find("--memory-budget"), std::string::npos) << reason;
  }
}

// The driver's own out-of-memory path (--no-memory-precheck: GL_OUT_OF_MEMORY, VK_ERROR_OUT_OF_*_MEMORY),
// where it can be reached without harm: on a CPU driver, whose targets are host memory, an address-space
// limit makes the 16384 cube fail to allocate. A GPU holds that cube in device memory, and vendor drivers may
// crash rather than fail under an address-space limit, so there the test says why it does not run.
TEST_F(CliRun, DriverOutOfMemoryFailsTheCaseAndTheMatrixGoesOn) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: ulimit -v cannot apply under it";
#else
  const std::string list = run("list").out;
  int ran = 0;
  for (std::string backend : {"gl", "vulkan"}) {
    const size_t line = list.find("  " + backend + ": ");
    if (line == std::string::npos ||
        list.compare(line, backend.size() + 15, "  " + backend + ": unavailable") == 0)
      continue;
    if (list.substr(line, list.find('\n', line) - line).find("host memory (CPU driver)") == std::string::npos)
      continue;
    SCOPED_TRACE(backend);
    ++ran;
    fs::path out = scratch("oom_driver_" + backend);
    std::string cmd = "ulimit -v 3000000; exec " + std::string(OMNISHADOW_BINARY) + " run --backend " +
                      backend +
                      " --scene room --cube 16384,64 --technique six_pass --filter hard --frames 1 --warmup 0"
                      " --no-images --no-accuracy --benchmark_repetitions=1 --no-memory-precheck --out " +
                      out.string() + " >/dev/null 2>&1";
    int status = std::system(("bash -c '" + cmd + "'").c_str());
    ASSERT_TRUE(WIFEXITED(status)) << "the run must not die";
    EXPECT_EQ(WEXITSTATUS(status), 0);
    const std::string reason = out_of_memory_then_ok(out);
    EXPECT_TRUE(reason.find("out of") != std::string::npos || reason.find("OUT_OF") != std::string::npos)
        << reason;
  }
  if (ran == 0)
    GTEST_SKIP()
        << "no backend here keeps its targets in host memory: the device holds the 16384 cube, and an "
           "address-space limit is no safe way to exhaust a GPU driver (PredictedOutOfMemory... covers the "
           "planned path)";
#endif
}

// The numerical-stability suite's invariants (scenes/extremes/, docs/extremes.md), on GL: no NaN/Inf anywhere
// in the read-back buffers; bounded error where the tutorials' settings hold (the room at 1:1e6 near/far and
// with zero-area triangles stays within 0.3% of exact visibility, measured 0.09-0.10%); the far-from-origin
// remedy works (offset 1e6: 3.1% without, 0.09% with /rebase; bound 0.2%); a light moving by ~1e-5 units per
// frame flips under 0.5% of pixels (measured 0). One six_pass/hard run over scenes/extremes with `args`; the
// parsed results.json (null when the run failed).
nlohmann::json run_extremes(const std::string& name, const std::string& args) {
  fs::path out = scratch(name);
  const std::string filter = args.find("--filter") == std::string::npos ? " --filter hard" : "";
  Outcome o =
      run("run --scenes-dir " + std::string(OMNISHADOW_TEST_SCENES_DIR) + "/extremes --technique six_pass" +
          filter + " --frames 1 --warmup 0 --benchmark_repetitions=1 --light-radius 0 --no-images " + args +
          " --out " + out.string());
  EXPECT_EQ(o.exit_code, 0) << o.err;
  if (o.exit_code != 0) return nullptr;
  return nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
}

TEST_F(CliRun, ExtremesHoldTheirStatedBounds) {
  auto j = run_extremes("extremes",
                        "--scene nf_1e6,degenerate,offset_1e6,stability_tiny_steps,light_on_floor"
                        " --remedy none,rebase --cube 512 --stability");
  ASSERT_FALSE(j.is_null());
  int checked = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    std::string id = c["id"];
    std::string scene = c["axes"]["scene"];
    bool rebased = c["axes"]["remedies"] == "rebase";
    if (scene == "offset_1e6" && !rebased) {
      // Far from the origin the cube itself is wrong (float positions at 1e6 step by 0.06): the cube-texel
      // check says so whatever the camera sees; rebased, it holds.
      EXPECT_EQ(c["status"], "failed_check") << id;
      EXPECT_NE(c["reason"].get<std::string>().find("cube_texels"), std::string::npos) << c["reason"];
    } else {
      ASSERT_EQ(c["status"], "ok") << id << ": " << c["reason"];
    }
    for (const auto& [buffer, count] : c["non_finite"].items()) EXPECT_EQ(count, 0) << id << " " << buffer;
    double error = c["accuracy"]["misclassified_percent"];
    if (scene == "nf_1e6" || scene == "degenerate" || scene == "stability_tiny_steps") {
      EXPECT_LT(error, 0.3) << id;
    }
    if (scene == "offset_1e6") {
      if (rebased)
        EXPECT_LT(error, 0.2) << id;
      else
        EXPECT_GT(error, 1.0) << id << ": the extreme no longer breaks?";
    }
    if (scene == "stability_tiny_steps") {
      EXPECT_LT(c["stability"]["flicker_percent"].get<double>(), 0.5) << id;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 10);
}

// Where a variant breaks, the result says so, and a remedy measured on and off in one run repairs it: a light
// inside a closed caster sees through it with back-face culling (measured 98.9% misclassified) and not with
// two-sided casters (0%); without bias, acne misclassifies about half the room (49%).
// Without --max-error, a hard comparison (hard, and hw_compare2x2's 2x2 bilinear of 0/1 comparisons) has a
// default limit (5% of pixels misclassified), not the soft filters' 15%: a 2-texel cube (about 40%) fails it
// with the measured error; the same case with --max-error 50 does not.
TEST_F(CliRun, HardShadowsHaveADefaultErrorLimit) {
  auto j = run_extremes("default_limit", "--scene nf_25 --cube 2,512 --filter hard,hw_compare2x2");
  ASSERT_FALSE(j.is_null());
  int broken = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    double e = c["accuracy"]["misclassified_percent"];
    EXPECT_EQ(c["status"], e > 5.0 ? "failed_quality" : "ok") << c["id"] << " " << e;
    if (e > 5.0) {
      ++broken;
      EXPECT_NE(c["reason"].get<std::string>().find("default limit for hard comparisons 5%"),
                std::string::npos)
          << c["reason"];
    }
  }
  EXPECT_EQ(j["omnishadow"]["cases"].size(), 4u);
  EXPECT_EQ(broken, 2) << "cube 2 breaks with either filter, cube 512 with neither";
  auto relaxed = run_extremes("relaxed_limit", "--scene nf_25 --cube 2 --max-error 99");
  ASSERT_FALSE(relaxed.is_null());
  EXPECT_EQ(relaxed["omnishadow"]["cases"][0]["status"], "ok");
}

TEST_F(CliRun, RemediesAreMeasuredOnAndOff) {
  auto j = run_extremes("remedies",
                        "--scene light_in_caster,nf_25 --remedy none,two_sided,bias0 --cube 256 "
                        "--max-error 5");
  ASSERT_FALSE(j.is_null());
  for (const auto& c : j["omnishadow"]["cases"]) {
    // Beyond --max-error 5: failed_quality with the measured error in the reason and as a figure; within it:
    // ok.
    double e = c["accuracy"]["misclassified_percent"];
    EXPECT_EQ(c["status"], e > 5.0 ? "failed_quality" : "ok") << c["id"];
    if (e > 5.0) {
      EXPECT_EQ(c["findings"][0]["check"], "max_error");
      EXPECT_DOUBLE_EQ(c["findings"][0]["figures"]["misclassified_percent"].get<double>(), e);
    }
    if (e > 5.0) {
      EXPECT_NE(c["reason"].get<std::string>().find("exact visibility"), std::string::npos) << c["reason"];
    }
  }
  std::map<std::string, double> error;
  for (const auto& c : j["omnishadow"]["cases"])
    error[c["axes"]["scene"].get<std::string>() + " " + c["axes"]["remedies"].get<std::string>()] =
        c["accuracy"]["misclassified_percent"];
  ASSERT_EQ(error.size(), 6u);
  EXPECT_GT(error["light_in_caster none"], 90.0);
  EXPECT_LT(error["light_in_caster two_sided"], 0.5);
  EXPECT_LT(error["nf_25 none"], 0.3);
  EXPECT_GT(error["nf_25 bias0"], 10.0);
  EXPECT_NEAR(error["nf_25 two_sided"], error["nf_25 none"], 0.05)
      << "two-sided casters change nothing else here";
}

}  // namespace

namespace {

// A run with faults injected into the cases that match `regex` (--inject-crash or --inject-hang) in the
// checks or the timed rounds, on both APIs where Vulkan is here: the matrix of 2 backends x 2 techniques.
struct FaultRun {
  Outcome outcome;
  nlohmann::json results;
};
FaultRun run_with_fault(const std::string& name, const std::string& fault) {
  std::string why;
  const std::string backends = vulkan_available(why) ? "gl,vulkan" : "gl";
  const fs::path out = scratch(name);
  FaultRun f;
  f.outcome =
      run("run --backend " + backends +
          " --scene room --cube 16 --frame 32x24 --technique six_pass,geometry_shader "
          "--filter hard --frames 2 --warmup 0 --no-accuracy --images none --benchmark_repetitions=2 " +
          fault + " --out " + out.string());
  if (fs::exists(out / "results.json"))
    f.results = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
  return f;
}

// Each case id to its status; the crashed ones' reasons checked by the caller.
std::map<std::string, nlohmann::json> cases_by_id(const nlohmann::json& results) {
  std::map<std::string, nlohmann::json> out;
  for (const auto& c : results["omnishadow"]["cases"]) out[c["id"].get<std::string>()] = c;
  return out;
}

void expect_one_case_each(const FaultRun& f, const std::string& reason_part, const std::string& step) {
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
  // A fresh process after each crash, unless the crash was the matrix's last case.
  const bool last_crashed = f.results["omnishadow"]["cases"].back()["status"] == "crashed";
  EXPECT_EQ(f.results["omnishadow"]["worker_processes"].get<int>(), crashed + (last_crashed ? 0 : 1));
  std::vector<std::string> order;  // matrix order kept: each backend's six_pass before its geometry_shader
  for (const auto& c : f.results["omnishadow"]["cases"]) order.push_back(c["id"]);
  for (size_t i = 1; i < order.size(); i += 2)
    EXPECT_NE(order[i].find("/geometry_shader/"), std::string::npos) << order[i] << " out of matrix order";
  EXPECT_NE(f.outcome.out.find("## Crashed cases"), std::string::npos) << f.outcome.out;
}

}  // namespace

// A case that kills the process (SIGSEGV in its check frame, injected: --inject-crash) costs that case alone:
// it is recorded `crashed` with the signal and the step, the run goes on in a fresh process from the next
// case, every finished case is in results.json, and the run exits 1. On GL and Vulkan.
TEST_F(CliRun, ACrashInTheChecksCostsOneCase) {
  const FaultRun f = run_with_fault("crash_checks", "--inject-crash /geometry_shader/");
  expect_one_case_each(f, "SIGSEGV", "check_frame");
  // The worker names the signal and its native frames before it dies (a driver's crash names its library).
  EXPECT_NE(f.outcome.err.find("omnishadow: worker died by SIGSEGV; native frames, innermost first:\n"),
            std::string::npos)
      << f.outcome.err;
}

// The same in the timed rounds: the cases timed before the crash keep their repetitions.
TEST_F(CliRun, ACrashInTheTimedRoundsCostsOneCase) {
  const FaultRun f = run_with_fault("crash_timed", "--inject-crash /geometry_shader/ --inject-in timed");
  expect_one_case_each(f, "SIGSEGV", "timed repetition");
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
                       "no progress for 10 s", "check_frame");
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
  const auto results = nlohmann::json::parse(omnishadow::bench::read_file((out / "results.json").string()));
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
