#pragma once
// The per-frame uniform block, built the same way for every backend: only the clip-space depth range differs.

#include "backends/common/case_config.h"
#include "backends/common/cube_faces.h"
#include "backends/common/gpu_layout.h"
#include "scenes/scene.h"

namespace omnishadow::gpu {

// From the case: frame size, injected fragment work, and optimizations.fit_range (the light's far plane
// fitted to the scene around this frame's light position instead of the scene's far).
FrameUniforms make_frame_uniforms(const scene::Scene& scene, int frame, const CaseConfig& config,
                                  cube::DepthRange range);

}  // namespace omnishadow::gpu
