#include "bench/run/renderdoc_frames.h"

#if __has_include(<renderdoc_app.h>)
#include <dlfcn.h>
#include <renderdoc_app.h>
#define OMNISHADOW_RENDERDOC 1
#endif

namespace omnishadow::bench::renderdoc {

#ifdef OMNISHADOW_RENDERDOC
namespace {

// Looked up once: RTLD_NOLOAD finds librenderdoc only where RenderDoc injected it (it is never loaded here).
RENDERDOC_API_1_6_0* api() {
  static RENDERDOC_API_1_6_0* const found = [] {
    RENDERDOC_API_1_6_0* a = nullptr;
    void* lib = dlopen("librenderdoc.so", RTLD_NOW | RTLD_NOLOAD);
    if (!lib) return a;
    auto get = reinterpret_cast<pRENDERDOC_GetAPI>(dlsym(lib, "RENDERDOC_GetAPI"));
    if (!get || get(eRENDERDOC_API_Version_1_6_0, reinterpret_cast<void**>(&a)) != 1) a = nullptr;
    return a;
  }();
  return found;
}

}  // namespace

bool loaded() { return api() != nullptr; }
// nullptr, nullptr: the context current on this thread (GL), which is the case's, as RenderDoc's API allows.
void start_frame() {
  if (api()) api()->StartFrameCapture(nullptr, nullptr);
}
bool end_frame() { return api() && api()->EndFrameCapture(nullptr, nullptr) == 1; }
#else
bool loaded() { return false; }
void start_frame() {}
bool end_frame() { return false; }
#endif

}  // namespace omnishadow::bench::renderdoc
