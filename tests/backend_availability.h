#pragma once
// Whether a test may skip a backend it cannot bring up. Only bringing the backend up may skip (no EGL, no
// Vulkan device, a missing layer: the machine's facts), and only where OMNISHADOW_REQUIRE_BACKENDS does not
// name it: CI sets "gl,vulkan", so a backend broken by a change fails its tests instead of skipping them.
// Anything that goes wrong after bring-up (loading a scene, rendering) is a failure, never a skip.

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>

namespace omnishadow::testing {

inline bool backend_required(const std::string& name) {
  const char* list = std::getenv("OMNISHADOW_REQUIRE_BACKENDS");
  if (!list) return false;
  std::stringstream words(list);
  for (std::string w; std::getline(words, w, ',');)
    if (w == name) return true;
  return false;
}

}  // namespace omnishadow::testing

// In SetUp or a test body: skip with `reason`, or fail where the backend is required.
#define OMNISHADOW_SKIP_UNAVAILABLE(name, reason)                                              \
  do {                                                                                         \
    if (::omnishadow::testing::backend_required(name))                                         \
      GTEST_FAIL() << "OMNISHADOW_REQUIRE_BACKENDS names " << (name) << ", but: " << (reason); \
    else                                                                                       \
      GTEST_SKIP() << (reason);                                                                \
  } while (0)
