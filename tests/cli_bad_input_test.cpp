// Bad input to the omnishadow binary: one line naming the culprit (the option, file or field) and exit code
// 2, never a crash. Every option that takes a value has a row here (tests/bad_input_coverage_test.py reads
// this table).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include "tests/cli_support.h"

namespace omnishadow::cli_test {
namespace {

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
        BadInput{"run --no-timing --precision 2 --out @OUT@", "--precision and --no-timing:"},
        BadInput{"run --sustain 5 --no-timing --out @OUT@", "--sustain and --no-timing:"},
        BadInput{"run --precision 0 --out @OUT@", "--precision"},
        BadInput{"run --precision 2 --precision-metric vram --out @OUT@", "--precision-metric"},
        BadInput{"run --out @OUT@ --benchmark_repetitions=zero", "--benchmark_repetitions: expected"},
        BadInput{"run --scene /nonexistent/model.glb --out @OUT@", "model.glb: cannot open model"},
        BadInput{"run --scene @TRUNCATED_GLB@ --out @OUT@", "truncated.glb: "},
        BadInput{"run --scene room,@OTHER_ROOM@ --out @OUT@", "would both be named 'room' in case ids"},
        BadInput{"run --light 1,2 --out @OUT@", "--light: expected X,Y,Z or X,Y,Z,AX,AY,AZ, got 2"},
        BadInput{"run --camera 1,nan,3 --out @OUT@", "--camera: 'nan' is not a finite number"},
        BadInput{"run --camera 1,2,3,0,0,0,4 --out @OUT@",
                 "--camera: expected X,Y,Z or X,Y,Z,TX,TY,TZ or X,Y,Z,TX,TY,TZ,AX,AY,AZ, got 7"},
        BadInput{"run --light 1,2,3,0,0,0,1,0,0 --out @OUT@",
                 "--light: expected X,Y,Z or X,Y,Z,AX,AY,AZ, got 9"},
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
        BadInput{"run --atlas-replan 1.5 --out @OUT@", "--atlas-replan: '1.5' is not a frame interval"},
        BadInput{"run --atlas-hysteresis 4 --out @OUT@", "--atlas-hysteresis: '4' is not a hysteresis"},
        BadInput{"run --staleness-frames -1 --out @OUT@",
                 "--staleness-frames: Value -1 not in range 0 to 10000"},
        BadInput{"run --isolation thread --out @OUT@", "--isolation: 'thread' is not process or none"},
        BadInput{"run --case-timeout-s nan --out @OUT@", "--case-timeout-s: 'nan' is not a finite number"},
        BadInput{"run --capture-max-mb 0 --out @OUT@", "--capture-max-mb"},
        BadInput{"run --capture-tool apitrace --out @OUT@", "--capture-tool: apitrace not in"},
        BadInput{"run --inject-crash '(' --out @OUT@", "--inject-crash: '(' is not a regular expression"},
        BadInput{"run --inject-hang [ --out @OUT@", "--inject-hang: '[' is not a regular expression"},
        BadInput{"run --crash-retries 9 --out @OUT@", "--crash-retries: Value 9 not in range 0 to 5"},
        BadInput{"run --inject-attempts -1 --out @OUT@", "--inject-attempts: Value -1 not in range 0 to 6"},
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

}  // namespace
}  // namespace omnishadow::cli_test
