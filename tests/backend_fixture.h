#pragma once
// The backend suite's fixture: one backend per API for the whole suite (Vulkan under the validation layer,
// whose messages fail the test), the room loaded, and the means the tests share (a room case, a rendered
// check frame, point-light truth). A backend this machine cannot bring up is skipped with the reason it gave.

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

#include "backends/backend.h"
#include "backends/reference/ray_caster.h"
#include "bench/truth/accuracy.h"
#include "tests/backend_availability.h"
#include "tests/optimization_checks.h"

namespace omnishadow {

inline const std::string kScenes = OMNISHADOW_TEST_SCENES_DIR;

// Vulkan always runs with the validation layer (its messages fail the test); GL without its debug context,
// whose KHR_debug capture has its own test below.
inline std::map<std::string, std::string> options_for(const std::string& name) {
  if (name == "vulkan") return {{"api_checks", "1"}};
  return {};
}

class BackendTest : public ::testing::TestWithParam<std::string> {
 protected:
  struct Shared {
    std::unique_ptr<Backend> backend;
    std::unique_ptr<scene::Scene> room;
    std::string skip_reason;
  };
  // One backend per API for the whole suite: bringing one up costs more than most tests. Released in
  // TearDownTestSuite, before main returns: a Vulkan device destroyed by a static destructor would outlive
  // the loader and its layers (a crash at exit).
  static std::map<std::string, Shared>& all() {
    static std::map<std::string, Shared> backends;
    return backends;
  }
  static Shared& shared(const std::string& name) {
    Shared& s = all()[name];
    if (!s.backend && s.skip_reason.empty()) {
      try {
        s.backend = create_backend(name, options_for(name));
      } catch (const std::exception& e) {
        s.skip_reason = "backend " + name + " cannot be brought up on this machine: " + e.what();
        return s;
      }
      // Past bring-up nothing skips: a scene that does not load is a failure of the test (SetUp's exception).
      s.room = std::make_unique<scene::Scene>(scene::load_scene_file(kScenes + "/room.json"));
      s.backend->load(*s.room);
    }
    return s;
  }
  static void TearDownTestSuite() { all().clear(); }

  void SetUp() override {
    Shared& s = shared(GetParam());
    if (!s.backend) OMNISHADOW_SKIP_UNAVAILABLE(GetParam(), s.skip_reason);
    backend_ = s.backend.get();
    room_ = s.room.get();
    backend_->load(*room_);  // a test may leave another scene loaded
  }
  void TearDown() override {
    if (!backend_) return;
    std::vector<std::string> messages = backend_->drain_api_errors();
    EXPECT_TRUE(messages.empty()) << messages.size() << " API message(s), first: " << messages.front();
  }

  CaseConfig room_case(Technique t, Filter f = Filter::hard, int cube = 512,
                       Storage s = Storage::linear_depth) const {
    return testing::room_case(GetParam(), t, f, cube, s);
  }
  Images render(const CaseConfig& c, int frame = 0) {
    backend_->configure(c);
    backend_->render(frame, FrameKind::check);
    return backend_->read_back();
  }
  bench::Truth point_truth(const Images& img, int frame) const {
    reference::RayCaster caster(*room_);
    bench::TruthOptions point_only;
    point_only.light_radius = 0.0f;
    return bench::compute_truth(caster, *room_, frame, img, point_only);
  }

  Backend* backend_ = nullptr;
  const scene::Scene* room_ = nullptr;
};

}  // namespace omnishadow
