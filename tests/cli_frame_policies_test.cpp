// The per-frame policies of many lights end to end, with --check on both APIs: what each frame renders and
// shades (view culling, clustered lists), a walking camera, an atlas re-planned along the walk, update
// budgets and their staleness, and moving casters with the static cache. Every case is held to six_pass
// unculled and to exact visibility of the frame it checks.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "tests/cli_support.h"

namespace omnishadow::cli_test {
namespace {

// Whether a culled case's lit frame was compared with an unculled one (its reference: six_pass, no /view).
bool held_to_unculled(const nlohmann::json& c) {
  for (const auto& check : c["checks"])
    if (check["name"] == "lit" && check["against"].get<std::string>().find("/view") == std::string::npos)
      return true;
  return false;
}

// Culled to the view from mid-hall and shaded from clustered lists: lamps behind the camera and faces turned
// away get no pass, which results.json counts, and every case still passes six_pass unculled and unclustered,
// its pixels' faces check and its clusters' check; with every light in one pass it is unsupported with its
// reason.
TEST_F(CliRun, ViewCullingCountsWhatItLeftOutAndPassesEveryCheck) {
  const std::string backends = available_backends();
  fs::path out = scratch("view");
  Outcome o = run(
      "run --backend " + backends +
      " --scene hall --light-count 16 --camera 0,3,0,20,2,0 --optimize view+clusters --cube 16 --frame 96x64"
      " --technique six_pass,vs_layer --light-grouping per_light,all_lights --filter pcf_disk20"
      " --frames 1 --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
      out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
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
    EXPECT_TRUE(held_to_unculled(c)) << c["id"] << ": its lit frame against six_pass unculled";
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
  j = results_of(beside);
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    EXPECT_GT(c["shadow_plan"]["view_culling"]["faces_culled"].get<int>(), 0) << c["id"];
    EXPECT_GT(c["moments"]["values"].get<int>(), 0) << c["id"] << ": the moments check ran";
  }
}

// The camera walked 16 units back down the hall (--camera's sway), checked at frame 188 where the walk ends:
// every case, culled to that frame's view and shaded from its lists, passes six_pass unculled and its truth,
// which cast from where the camera stands then; results.json keeps the sway as given. Under an update budget
// the walk brings faces into view that view culling left empty: each renders at once, beyond the budget, so
// no frame of the staleness sequence reads a face that holds nothing.
TEST_F(CliRun, AWalkingCameraIsCheckedWhereTheFrameHasIt) {
  const std::string backends = available_backends();
  fs::path out = scratch("walk");
  Outcome o = run("run --backend " + backends +
                  " --scene hall --light-count 16 --camera 0,3,0,20,2,0,-16,0,0 --check-frame 188"
                  " --optimize none,view+clusters --cube 32 --frame 96x64 --technique six_pass"
                  " --filter pcf_disk20 --frames 1 --warmup 0 --images none --check --max-error 100"
                  " --benchmark_repetitions=1 --out " +
                  out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
  EXPECT_EQ(j["omnishadow"]["options"]["camera"], "0,3,0,20,2,0,-16,0,0");
  int culled = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    EXPECT_GT(c["accuracy"]["pixels"].get<int>(), 0) << c["id"];
    if (c["id"].get<std::string>().find("/view") == std::string::npos) continue;
    ++culled;
    EXPECT_TRUE(held_to_unculled(c)) << c["id"];
  }
  EXPECT_EQ(culled, backends == "gl,vulkan" ? 2 : 1);
  fs::path budget = scratch("walk_budget");
  o = run(
      "run --backend " + backends +
      " --scene hall --light-count 16 --camera 0,3,0,20,2,0,-16,0,0 --update-budget 8 --staleness-frames 6"
      " --optimize view --cube 32 --frame 96x64 --technique six_pass,geometry_shader --filter hard --frames 1"
      " --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
      budget.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  j = results_of(budget);
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    int beyond = 0;
    for (const auto& f : c["staleness"]["frames"])
      beyond += f["frame"].get<int>() > 0 && f["faces_rendered"].get<int>() > 8;
    EXPECT_GT(beyond, 0) << c["id"] << ": a face the walk brought into view rendered beyond the budget";
  }
}

// An atlas re-planned every 4 frames along the walk: checked at frame 188 with the tiles planned there (every
// check holds, results.json says which frame planned them, and they are not frame 0's), and under an update
// budget the staleness sequence counts the lights a re-plan moved apart from the budget.
TEST_F(CliRun, AnAtlasReplannedOnTheWalkIsCheckedWithTheFramesTiles) {
  const std::string backends = available_backends();
  fs::path out = scratch("replan");
  Outcome o =
      run("run --backend " + backends +
          " --scene hall --light-count 8 --camera 0,3,0,20,2,0,-16,0,0 --check-frame 188 --layout atlas"
          " --atlas-tiles by_coverage --shadow-budget 32K --atlas-replan none,4 --update-budget 12"
          " --staleness-frames 24 --cube 32 --frame 96x64 --technique six_pass --filter hard --frames 1"
          " --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const auto j = results_of(out);
  std::map<std::string, nlohmann::json> sizes;  // backend -> face sizes, planned once
  int replanned = 0, relocated = 0;
  for (const auto& c : j["omnishadow"]["cases"]) {
    EXPECT_EQ(c["status"], "ok") << c.dump().substr(0, 2000);
    const auto& atlas = c["shadow_plan"]["atlas"];
    if (c["axes"]["atlas_replan_frames"] == 0) {
      sizes[c["axes"]["backend"]] = atlas["face_sizes"];
      continue;
    }
    ++replanned;
    EXPECT_EQ(atlas["planned_at_frame"], 188) << c["id"];
    for (const auto& f : c["staleness"]["frames"]) relocated += f["lights_relocated"].get<int>();
  }
  EXPECT_EQ(replanned, backends == "gl,vulkan" ? 2 : 1);
  EXPECT_GT(relocated, 0) << "the sequence's walk moved blocks";
  for (const auto& c : j["omnishadow"]["cases"]) {
    if (c["axes"]["atlas_replan_frames"] != 4) continue;
    EXPECT_NE(c["shadow_plan"]["atlas"]["face_sizes"], sizes[c["axes"]["backend"]]) << c["id"];
  }
}

// An update budget on both APIs: the check frame's maps are whole (every check holds), and the sequence from
// a fresh start renders at most the budget's faces a frame after the first, every face read within its wait
// bound; the stale faces of the swaying lamps and of those the moving casters reach cost misclassified
// pixels.
TEST_F(CliRun, UpdateBudgetRendersAtMostItsFacesAndReportsWhatStalenessCosts) {
  const std::string backends = available_backends();
  fs::path out = scratch("update_budget");
  Outcome o = run("run --backend " + backends +
                  " --scene hall --light-count 8 --update-budget none,2,12 --staleness-frames 12 --cube 32"
                  " --frame 96x64 --technique six_pass,geometry_shader --filter hard --frames 1 --warmup 0"
                  " --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
                  out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
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
  j = results_of(plain);
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
  const std::string backends = available_backends();
  fs::path out = scratch("moving_casters");
  Outcome o =
      run("run --backend " + backends +
          " --scene hall --light-count 4 --check-frame 90 --optimize none,cache --staleness-frames 4"
          " --cube 64 --frame 200x150"
          " --technique six_pass,geometry_shader,vs_layer,mesh_shader --emulate-mesh-shader --filter hard"
          " --frames 2 --warmup 0 --images none --check --max-error 100 --benchmark_repetitions=1 --out " +
          out.string());
  ASSERT_EQ(o.exit_code, 0) << o.err;
  auto j = results_of(out);
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

}  // namespace
}  // namespace omnishadow::cli_test
