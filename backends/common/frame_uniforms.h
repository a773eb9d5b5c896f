#pragma once
// The per-frame uniform block, built the same way for every backend: only the clip-space depth range differs.

#include "backends/common/cube_faces.h"
#include "backends/common/gpu_layout.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

// injected_work: iterations of extra fragment work per lighting fragment (CaseConfig::injected_work).
FrameUniforms make_frame_uniforms(const scene::Scene& scene, int frame, int width, int height,
                                  cube::DepthRange range, int injected_work);

}  // namespace omnishadow::gpu
