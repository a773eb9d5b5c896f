#version 450
// 2D shadow map pass for a spot or directional light (the directional notes): plain projective depth, no colour output.
// pass.face selects the light (its layer of the 2D map array and its view-projection).
#include "common.glsl"
#include "raster_perturb.glsl"

layout(location = 0) in vec3 in_position;

// The maps' layers are --cube texels a side, whichever light's uniforms are bound.
void main() { gl_Position = perturb_raster_in(frame.map_view_proj[pass.face] * vec4(in_position, 1.0), 1.0); }
