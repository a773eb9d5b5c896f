// Regression decisions: the U-test against scipy's figures, Holm's correction, and `compare` on synthetic
// runs (timing, work counters, images, devices, bad input).

#include "bench/report/compare.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "bench/io/file_io.h"
#include "bench/io/image_io.h"
#include "bench/io/statistics.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(Statistics, MannWhitneyMatchesScipy) {
  // scipy.stats.mannwhitneyu(..., alternative='two-sided'), exact and asymptotic with continuity.
  EXPECT_NEAR(mann_whitney_p({1, 2, 3}, {4, 5, 6}), 0.1, 1e-12);
  EXPECT_NEAR(mann_whitney_p({1, 2, 3, 4, 5}, {6, 7, 8, 9, 10}), 2.0 / 252.0, 1e-12);
  EXPECT_NEAR(mann_whitney_p({1.5, 2.1, 3.3, 0.4}, {2.0, 5.5, 4.1, 6.2, 7.0}), 0.06349206349206349, 1e-12);
  EXPECT_NEAR(mann_whitney_p({1, 2, 2, 3, 4, 5}, {3, 4, 4, 5, 6, 7, 8}), 0.0364709007712748, 1e-9);
  // Nine against nine, as the CI matrix's repetitions: exact without ties, asymptotic with one tie.
  EXPECT_NEAR(mann_whitney_p({10.1, 10.3, 9.8, 10.0, 10.2, 10.4, 9.9, 10.15, 10.05},
                             {11.0, 10.9, 11.2, 10.8, 11.1, 10.95, 11.3, 10.85, 11.05}),
              4.113533525298231e-05, 1e-12);
  EXPECT_NEAR(mann_whitney_p({10.1, 10.3, 9.8, 10.0, 10.2, 10.4, 9.9, 10.1, 10.05},
                             {11.0, 10.9, 11.2, 10.8, 11.1, 10.95, 11.3, 10.85, 11.05}),
              0.0004094601088531576, 1e-12);
  EXPECT_EQ(mann_whitney_p({}, {1, 2}), 1.0);
  EXPECT_EQ(mann_whitney_p({3, 3, 3}, {3, 3, 3}), 1.0);
}

TEST(Statistics, HolmControlsTheFamily) {
  std::vector<double> adjusted = holm_adjust({0.01, 0.04, 0.03, 0.5});
  EXPECT_NEAR(adjusted[0], 0.04, 1e-12);  // 4 x 0.01
  EXPECT_NEAR(adjusted[2], 0.09, 1e-12);  // 3 x 0.03
  EXPECT_NEAR(adjusted[1], 0.09, 1e-12);  // max(2 x 0.04, 0.09): monotone
  EXPECT_NEAR(adjusted[3], 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(median({3, 1, 2, 10}), 2.5);
}

TEST(Statistics, TooFewRepetitionsCannotBeFlaggedOverManyCases) {
  EXPECT_NEAR(smallest_p(6, 6), 2.0 / 924.0, 1e-15);  // 2 / C(12, 6): every value of one side below the other
  EXPECT_NEAR(smallest_p(5, 5), mann_whitney_p({1, 2, 3, 4, 5}, {6, 7, 8, 9, 10}), 1e-15);
  // The CI matrix's 24 cases: Holm's first step needs p < 0.05 / 24 = 0.00208; 6 a side reach 0.00216 at
  // best.
  EXPECT_FALSE(can_resolve(6, 6, 24));
  EXPECT_TRUE(can_resolve(7, 7, 24));
  EXPECT_TRUE(can_resolve(6, 7, 24));  // 2 / C(13, 6) = 0.00117
  EXPECT_EQ(fewest_resolving_repetitions(24), 7);
  EXPECT_EQ(fewest_resolving_repetitions(96), 8);
  EXPECT_EQ(fewest_resolving_repetitions(1), 4);  // 3 a side: p >= 0.1
  EXPECT_EQ(fewest_resolving_repetitions(24, 0.01), 8);
  EXPECT_GE(fewest_resolving_repetitions(5000), 9);  // past the exact table's 25 a side it still ends
}

// A run folder with one results.json written from scratch, like `omnishadow run` writes it.
class CompareTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("omnishadow_compare_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write_run(const std::string& name, const std::map<std::string, std::vector<double>>& times,
                        uint64_t gs_primitives = 432, float shadow_value = 0.0f,
                        const std::string& renderer = "llvmpipe", double clock_mhz = -1) {
    fs::path run = dir_ / name;
    fs::create_directories(run / "img");
    json doc{{"context", json::object()}, {"benchmarks", json::array()}};
    json cases = json::array();
    for (const auto& [id, samples] : times) {
      for (size_t i = 0; i < samples.size(); ++i)
        doc["benchmarks"].push_back({{"name", id + "/iterations:3/manual_time"},
                                     {"run_type", "iteration"},
                                     {"real_time", samples[i]},
                                     {"cpu_time", 0.1},
                                     {"time_unit", "ms"},
                                     {"omnishadow_case", id}});
      std::string file = "img/" + std::to_string(cases.size()) + ".pfm";
      std::vector<float> pixels(16, 0.0f);
      pixels[5] = shadow_value;
      write_pfm((run / file).string(), 4, 4, 1, pixels);
      cases.push_back({{"id", id},
                       {"status", "ok"},
                       {"images", {{"shadow_factor", file}}},
                       {"counters", {{"shadow", {{"valid", true}, {"gs_primitives", gs_primitives}}}}}});
      if (clock_mhz > 0)
        cases.back()["device_state"] = {
            {"source", "nvml"},
            {"samples", json::array({{{"clock_mhz", clock_mhz}}, {{"clock_mhz", clock_mhz}}})}};
    }
    doc["omnishadow"] = {{"format", "omnishadow-results/1"},
                         {"cases", cases},
                         {"system", {{"LP_NUM_THREADS", "unset"}}},
                         {"devices", {{"gl", {{"renderer", renderer}, {"version", "4.5 Mesa 22.3.6"}}}}}};
    write_file_atomic((run / "results.json").string(), doc.dump());
    return run.string();
  }

  static json read_doc(const std::string& run) {
    return json::parse(read_file((fs::path(run) / "results.json").string()));
  }
  static void write_doc(const std::string& run, const json& doc) {
    write_file_atomic((fs::path(run) / "results.json").string(), doc.dump());
  }
  static void set_status(const std::string& run, const std::string& id, const std::string& status,
                         const std::string& reason) {
    json doc = read_doc(run);
    for (json& c : doc["omnishadow"]["cases"])
      if (c["id"] == id) c["status"] = status, c["reason"] = reason;
    write_doc(run, doc);
  }
  static void set_complete(const std::string& run, bool complete) {
    json doc = read_doc(run);
    doc["omnishadow"]["complete"] = complete;
    write_doc(run, doc);
  }

  fs::path dir_;
};

const std::vector<double> kBase = {10.0, 10.2, 9.9, 10.1, 10.0, 9.8, 10.3, 10.1, 9.9};

std::vector<double> scaled(const std::vector<double>& v, double f) {
  std::vector<double> out;
  for (double x : v) out.push_back(x * f);
  return out;
}

TEST_F(CompareTest, TimingVerdictsNeedSignificanceAndEffect) {
  std::string base = write_run("base", {{"a", kBase}, {"b", kBase}, {"c", kBase}});
  std::string fresh =
      write_run("new", {{"a", scaled(kBase, 1.2)}, {"b", scaled(kBase, 1.02)}, {"c", scaled(kBase, 0.8)}});
  CompareOptions o;
  o.min_effect = 0.05;
  Comparison c = compare_runs(load_run(base), load_run(fresh), o);
  ASSERT_EQ(c.cases.size(), 3u);
  EXPECT_EQ(c.cases[0].verdict, "regression");
  EXPECT_NEAR(c.cases[0].change, 0.2, 1e-9);
  EXPECT_EQ(c.cases[1].verdict, "no change") << "2% is significant but below the minimum effect";
  EXPECT_EQ(c.cases[2].verdict, "improvement");
  EXPECT_FALSE(c.cases[2].regressed());
  EXPECT_EQ(compare_command(base, fresh, o), 1);
  EXPECT_TRUE(fs::exists(fs::path(fresh) / "compare" / "summary.md"));
  EXPECT_EQ(compare_command(base, base, o), 0);
}

// --metric gpu tests the passes' GPU time (timer queries), only from repetitions whose timer passed its
// check: a GPU slowdown hidden in the wall time (CPU-bound frames) is found, an unreliable repetition's
// figure is not used, and a run without GPU times says so instead of passing.
TEST_F(CompareTest, GpuMetricTestsThePassesGpuTime) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string fresh = write_run("new", {{"a", kBase}});
  std::string no_gpu = write_run("no_gpu", {{"a", kBase}});
  auto add_gpu = [](const std::string& run, double factor, bool last_unreliable) {
    json doc = read_doc(run);
    size_t i = 0, n = doc["benchmarks"].size();
    for (json& b : doc["benchmarks"]) {
      const bool unreliable = last_unreliable && ++i == n;
      b["gpu_timer_reliable"] = unreliable ? 0.0 : 1.0;
      b["shadow_gpu_ms"] = unreliable ? 1000.0 : 0.3 * factor * b["real_time"].get<double>();
      b["lighting_gpu_ms"] = unreliable ? 1000.0 : 0.2 * factor * b["real_time"].get<double>();
    }
    write_doc(run, doc);
  };
  add_gpu(base, 1.0, false);
  add_gpu(fresh, 1.3, true);
  RunData fresh_run = load_run(fresh);
  ASSERT_EQ(fresh_run.gpu_samples["a"].size(), kBase.size() - 1) << "the unreliable repetition is left out";
  EXPECT_NEAR(load_run(base).gpu_samples["a"][0], 0.5 * kBase[0], 1e-9);
  CompareOptions o;
  EXPECT_EQ(compare_runs(load_run(base), fresh_run, o).cases[0].verdict, "no change")
      << "the wall time is the same";
  o.metric = "gpu";
  Comparison c = compare_runs(load_run(base), fresh_run, o);
  EXPECT_EQ(c.cases[0].verdict, "regression");
  EXPECT_NEAR(c.cases[0].change, 0.3, 0.02) << "+30% (medians of 9 and of the 8 reliable repetitions)";
  EXPECT_EQ(compare_runs(load_run(base), load_run(no_gpu), o).cases[0].verdict, "no GPU time");
  const fs::path gate = dir_ / "gate.json";
  write_file_atomic(gate.string(), R"({"metric": "gpu", "alpha": 0.01, "min_effect": 0.02})");
  CompareOptions from_gate;
  apply_gate_file(gate.string(), from_gate);
  EXPECT_EQ(from_gate.metric, "gpu");
}

// "No change" from samples too small to reach significance over the family says nothing: compare says so.
TEST_F(CompareTest, CasesTooSmallToFlagAreNamed) {
  std::map<std::string, std::vector<double>> base_times, new_times;
  const std::vector<double> six(kBase.begin(), kBase.begin() + 6);
  for (int i = 0; i < 24; ++i) {
    base_times["case" + std::to_string(i)] = six;
    new_times["case" + std::to_string(i)] = scaled(six, 2.0);
  }
  Comparison c =
      compare_runs(load_run(write_run("base", base_times)), load_run(write_run("new", new_times)), {});
  ASSERT_EQ(c.cases.size(), 24u);
  for (const CaseComparison& cc : c.cases) {
    EXPECT_FALSE(cc.resolvable) << cc.id;
    EXPECT_EQ(cc.verdict, "no change")
        << "twice as slow, yet 6 against 6 over 24 cases cannot reach p < 0.05/24";
  }
  const std::string note = c.resolution_note({});
  EXPECT_NE(note.find("24 of 24 timed cases cannot be flagged"), std::string::npos) << note;
  EXPECT_NE(note.find("needs 7 a side"), std::string::npos) << note;
  EXPECT_NE(comparison_table(c, {}).find(note), std::string::npos);
  EXPECT_EQ(comparison_json(c, {})["cases"][0]["resolvable"], false);

  Comparison few = compare_runs(load_run(write_run("base3", {{"a", six}})),
                                load_run(write_run("new3", {{"a", scaled(six, 2.0)}})), {});
  EXPECT_TRUE(few.cases[0].resolvable);
  EXPECT_EQ(few.cases[0].verdict, "regression");
  EXPECT_TRUE(few.resolution_note({}).empty());
}

// Runs of one device at different clocks are different measurements: compare shows both clocks.
TEST_F(CompareTest, ClockDifferencesBetweenRunsAreShown) {
  std::string base = write_run("base", {{"a", kBase}}, 432, 0.0f, "llvmpipe", 1980);
  std::string fresh = write_run("new", {{"a", kBase}}, 432, 0.0f, "llvmpipe", 1755);
  Comparison c = compare_runs(load_run(base), load_run(fresh), CompareOptions{});
  EXPECT_DOUBLE_EQ(c.base_clock_mhz, 1980);
  EXPECT_DOUBLE_EQ(c.new_clock_mhz, 1755);
  EXPECT_NE(c.clock_note().find("base 1980 MHz, new 1755 MHz (-11.4%)"), std::string::npos) << c.clock_note();
  EXPECT_NE(comparison_table(c, CompareOptions{}).find("1755 MHz"), std::string::npos);
  std::string plain = write_run("plain", {{"a", kBase}});
  EXPECT_TRUE(compare_runs(load_run(base), load_run(plain), CompareOptions{}).clock_note().empty());
}

// The same device made to run another program (a SPIR-V level, a GL profile): compare names each setting that
// differs, where both runs record it, and still compares (one device).
TEST_F(CompareTest, DeviceSettingsThatDifferAreShown) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string fresh = write_run("new", {{"a", kBase}});
  json b = read_doc(base), n = read_doc(fresh);
  b["omnishadow"]["devices"]["gl"]["extra"] = {
      {"gl_profile", "core"}, {"api_checks", "off"}, {"only_base", "x"}};
  n["omnishadow"]["devices"]["gl"]["extra"] = {{"gl_profile", "compatibility"}, {"api_checks", "off"}};
  write_doc(base, b);
  write_doc(fresh, n);
  Comparison c = compare_runs(load_run(base), load_run(fresh), CompareOptions{});
  ASSERT_EQ(c.setup_changes.size(), 1u);
  EXPECT_EQ(c.setup_changes[0], "gl gl_profile: core -> compatibility");
  EXPECT_NE(comparison_table(c, {}).find("setup differs: gl gl_profile: core -> compatibility"),
            std::string::npos);
  EXPECT_NE(comparison_markdown(c, {}).find("- gl gl_profile: core -> compatibility"), std::string::npos);
  EXPECT_EQ(comparison_json(c, {})["setup_changes"][0], "gl gl_profile: core -> compatibility");
  EXPECT_TRUE(compare_runs(load_run(base), load_run(base), CompareOptions{}).setup_changes.empty());
}

TEST_F(CompareTest, WorkAndImageChangesAreRegressionsWhateverTheTiming) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string work = write_run("work", {{"a", kBase}}, 72);
  std::string image = write_run("image", {{"a", kBase}}, 432, 1.0f);
  Comparison w = compare_runs(load_run(base), load_run(work), {});
  ASSERT_EQ(w.cases[0].work_changes.size(), 1u);
  EXPECT_EQ(w.cases[0].work_changes[0], "shadow gs_primitives 432 -> 72");
  EXPECT_TRUE(w.cases[0].regressed());
  Comparison i = compare_runs(load_run(base), load_run(image), {});
  ASSERT_EQ(i.cases[0].image_changes.size(), 1u);
  EXPECT_NE(i.cases[0].image_changes[0].find("6.25% of values differ (max 1)"), std::string::npos)
      << i.cases[0].image_changes[0];
  EXPECT_TRUE(fs::exists(fs::path(image) / "compare" / "diffs" / "a" / "diff_shadow_factor.png"));
}

// A case ok in the base that is missing from the new run fails the comparison; a case only in the new run is
// listed.
TEST_F(CompareTest, AMissingCaseIsAStatusRegressionANewCaseIsListed) {
  std::string base = write_run("base", {{"a", kBase}, {"gone", kBase}});
  std::string fresh = write_run("new", {{"a", kBase}, {"added", kBase}});
  Comparison c = compare_runs(load_run(base), load_run(fresh), {});
  EXPECT_EQ(c.cases.size(), 1u);
  EXPECT_EQ(c.only_in_base, std::vector<std::string>{"gone"});
  EXPECT_EQ(c.only_in_new, std::vector<std::string>{"added"});
  EXPECT_EQ(c.status_regressions, std::vector<std::string>{"gone: ok -> missing"});
  EXPECT_EQ(compare_command(base, fresh, {}), 1);
  std::string only_added = write_run("more", {{"a", kBase}, {"gone", kBase}, {"added", kBase}});
  EXPECT_EQ(compare_command(base, only_added, {}), 0) << "a new case alone is no regression";
}

// Statuses: ok -> failed_check, unsupported or interrupted fails and is listed first; a case that already
// failed in the base and still fails is not a new regression; an interrupted run's missing cases say so.
TEST_F(CompareTest, AStatusRegressionFailsTheComparison) {
  std::string base = write_run("base", {{"a", kBase}, {"b", kBase}, {"c", kBase}, {"d", kBase}});
  set_status(base, "d", "failed_check", "was failing");
  std::string fresh = write_run("new", {{"a", kBase}, {"b", kBase}, {"c", kBase}, {"d", kBase}});
  set_status(fresh, "a", "failed_check", "cube_texels: 3% of texels wrong");
  set_status(fresh, "b", "unsupported", "no geometry shader");
  set_status(fresh, "d", "failed_check", "still failing");
  Comparison c = compare_runs(load_run(base), load_run(fresh), {});
  EXPECT_EQ(c.status_regressions,
            (std::vector<std::string>{"a: ok -> failed_check (cube_texels: 3% of texels wrong)",
                                      "b: ok -> unsupported (no geometry shader)"}));
  EXPECT_TRUE(c.failed({}));
  EXPECT_EQ(comparison_table(c, {}).rfind("STATUS REGRESSION a: ok -> failed_check", 0), 0u)
      << "listed first";
  EXPECT_EQ(comparison_json(c, {})["failed"], true);
  EXPECT_EQ(compare_command(base, fresh, {}), 1);
  std::string cut = write_run("cut", {{"a", kBase}});
  set_complete(cut, false);
  Comparison i = compare_runs(load_run(base), load_run(cut), {});
  EXPECT_EQ(i.status_regressions.front(), "b: ok -> missing (the new run was interrupted)");
}

// Two runs with no case in common compare nothing: that is a failure, not a pass.
TEST_F(CompareTest, NoCaseInCommonFails) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string fresh = write_run("new", {{"b", kBase}});
  set_status(base, "a", "unsupported", "not here");  // so that no status regression is what fails it
  Comparison c = compare_runs(load_run(base), load_run(fresh), {});
  EXPECT_TRUE(c.status_regressions.empty());
  EXPECT_TRUE(c.cases.empty());
  EXPECT_NE(comparison_table(c, {}).find("no case in common"), std::string::npos);
  EXPECT_EQ(compare_command(base, fresh, {}), 1);
}

TEST_F(CompareTest, BadInputIsAClearError) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string other = write_run("other", {{"a", kBase}}, 432, 0.0f, "NVIDIA GeForce");
  auto message = [&](const std::string& b, const std::string& n) {
    try {
      compare_command(b, n, {});
    } catch (const CompareError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(base, other).find("different devices"), std::string::npos);
  write_file_atomic((dir_ / "truncated.json").string(), R"({"omnishadow": {"format": "omnishadow-res)");
  EXPECT_NE(message(base, (dir_ / "truncated.json").string()).find("not valid JSON"), std::string::npos);
  write_file_atomic((dir_ / "foreign.json").string(), R"({"context": {}, "benchmarks": []})");
  EXPECT_NE(message(base, (dir_ / "foreign.json").string()).find("not an omnishadow results file"),
            std::string::npos);
  EXPECT_NE(message(base, (dir_ / "missing").string()).find("cannot read"), std::string::npos);
  CompareOptions allow;
  allow.allow_device_mismatch = true;
  EXPECT_EQ(compare_command(base, other, allow), 0);
}

}  // namespace
}  // namespace omnishadow::bench

namespace omnishadow::bench {
namespace {

TEST_F(CompareTest, TimingCanBeReportedWithoutFailing) {
  std::string base = write_run("base", {{"a", kBase}});
  std::string slow = write_run("slow", {{"a", scaled(kBase, 1.5)}});
  CompareOptions report_only;
  report_only.timing_fails = false;
  EXPECT_EQ(compare_command(base, slow, report_only), 0);
  EXPECT_EQ(compare_command(base, slow, {}), 1);
  std::string work = write_run("work", {{"a", kBase}}, 1);
  EXPECT_EQ(compare_command(base, work, report_only), 1) << "work changes fail even when timing only reports";
}

}  // namespace
}  // namespace omnishadow::bench
