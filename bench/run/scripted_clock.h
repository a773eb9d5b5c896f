#pragma once
// The harness's test double for time (--inject-frame-ms MS). Every frame lasts MS milliseconds, plus 1% for
// each unit of the case's injected fragment work (--inject-fragment-work W: MS x (1 + W/100); that work is
// added to every fragment, so more of it is a slower frame), and every clock the harness reads says so: the
// frame's wall time, the process's CPU time, and each pass's wall and GPU time (half the frame each; a GPU
// figure only where the backend measures one). Tests about time (the warm-up and repetitions sized by time,
// a slower commit caught by the fleet's compare) then get one answer on every machine, however loaded. The
// frames are rendered as usual: work, images and checks are a measured run's.
#include "backends/backend.h"

namespace omnishadow::bench {

inline double scripted_frame_ms(double frame_ms, int injected_work) {
  return frame_ms * (1.0 + injected_work / 100.0);
}

// frame_ms 0: the clocks' own readings, untouched.
inline void apply_scripted_clock(double frame_ms, int injected_work, FrameTiming& t) {
  if (frame_ms <= 0) return;
  const double ms = scripted_frame_ms(frame_ms, injected_work);
  t.frame_wall_ms = ms;
  t.process_cpu_ms = ms;
  for (PassTiming* pass : {&t.shadow, &t.lighting}) {
    pass->cpu_wall_ms = ms / 2;
    pass->cpu_submit_ms = 0.0;  // recording and submission: none on a scripted device
    if (pass->gpu_ms >= 0) pass->gpu_ms = ms / 2;
  }
}

}  // namespace omnishadow::bench
