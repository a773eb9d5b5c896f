#pragma once
// Which cases can be run at all, by rules that hold on every backend (a compare sampler needs depth storage,
// a layout's technique, the light limits of each layout, the moments knobs, the update budget); each
// backend's supports() asks these first and adds its device's own limits.

#include <string>

#include "backends/common/case_config.h"

namespace omnishadow {

// Rules that hold on every backend (a compare sampler needs depth storage; sizes must be positive).
Support common_support(const CaseConfig& config);
// Whether the case's layers (the layout's layers per light times the light count) fit a device's array
// textures of at most `max_layers` layers (`limit`: the API's name for it).
Support layer_count_support(const CaseConfig& config, int max_layers, const std::string& limit);
// Whether the update budget (CaseConfig::update_budget_faces) refreshes a light's faces one by one: each face
// is a render pass of its own that clears only its own layer (six_pass over a light's six layers; an atlas
// clears the light's whole block) and nothing after the pass rewrites a face from the others (the moments
// blur does). Otherwise a refresh renders the whole light and costs its six faces.
bool refreshes_single_faces(const CaseConfig& config);

}  // namespace omnishadow
