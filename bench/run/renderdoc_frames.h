#pragma once
// RenderDoc's in-application API (renderdoc_app.h, Debian's librenderdoc-dev) where librenderdoc is loaded
// into this process: a capture run that `run --capture` starts under `renderdoccmd capture`
// (bench/cli/capture.h). The harness never presents, so RenderDoc has no frame of its own to capture: the
// check frame of each case is bracketed with StartFrameCapture/EndFrameCapture instead. Where librenderdoc is
// not loaded (every other run) nothing happens and nothing of RenderDoc is linked; a build without the header
// has the same no-ops.

namespace omnishadow::bench::renderdoc {

bool loaded();       // librenderdoc is in this process and gave its API
void start_frame();  // before the check frame's first command
bool end_frame();    // after its last: whether RenderDoc wrote a capture

}  // namespace omnishadow::bench::renderdoc
