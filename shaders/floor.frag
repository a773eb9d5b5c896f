#version 450
// The lighting floor: the frame rasterised and written with no lighting and no shadow lookup, the albedo as the
// colour. What every lighting variant pays at the least (interpolation, depth test, one RGBA8 write per fragment);
// a lighting pass's time as a multiple of this is what its shading costs. Takes lighting.vert's outputs.
layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec3 albedo;

layout(location = 0) out vec4 out_color;

// Every input is read, so that the interface matches lighting.vert's outputs (an output nothing consumes is a
// validation warning) and the vertex work stays the lighting pass's. glslc folds a literal 0 * x away, inputs
// and all; a specialisation constant survives it and the driver folds it when it builds the pipeline.
#ifdef VULKAN
layout(constant_id = 0) const float kZero = 0.0;
#else
const float kZero = 0.0;
#endif

void main() { out_color = vec4(albedo + kZero * (world_position + world_normal), 1.0); }
