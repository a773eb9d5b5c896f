#pragma once
// Timer and pipeline-statistics queries for one frame's two passes (shadow, lighting).

#include <epoxy/gl.h>

#include <array>

#include "backends/backend.h"

namespace omnishadow::gl {

enum Pass { kShadowPass = 0, kLightingPass = 1, kPassCount = 2 };

class FrameQueries {
 public:
  explicit FrameQueries(bool has_pipeline_statistics);
  ~FrameQueries();
  FrameQueries(const FrameQueries&) = delete;
  FrameQueries& operator=(const FrameQueries&) = delete;

  void begin_timer(Pass pass) { glBeginQuery(GL_TIME_ELAPSED, timers_[pass]); }
  void end_timer() { glEndQuery(GL_TIME_ELAPSED); }
  double timer_ms(Pass pass) const;  // waits for the result

  bool has_statistics() const { return has_statistics_; }
  void begin_statistics(Pass pass);
  void end_statistics();
  PassCounters statistics(Pass pass) const;  // waits for the results

 private:
  static constexpr int kStatisticCount = static_cast<int>(kPipelineStatistics.size());
  bool has_statistics_;
  std::array<GLuint, kPassCount> timers_{};
  std::array<std::array<GLuint, kStatisticCount>, kPassCount> statistics_{};
};

}  // namespace omnishadow::gl
