// Shared by the GL and Vulkan backends. The block layout mirrors FrameUniforms in
// backends/common/gpu_layout.h; change both together.

layout(std140, binding = 0) uniform FrameUniforms {
  mat4 camera_view_proj;
  mat4 face_view_proj[6];  // face order +X, -X, +Y, -Y, +Z, -Z (backends/common/cube_faces.h)
  vec4 camera_position;    // xyz, world units
  vec4 light_position;     // xyz world units; w = far plane of the light (world units)
  vec4 light_color;        // rgb; w = near plane of the light
  vec4 knobs;              // x = injected fragment work (iterations; 0 unless --inject-fragment-work);
                           // y = PCF radius scale (1 = the tutorials' kernels; --pcf-scale);
                           // z = the radius of the light PCSS imitates, world units (kPcssLightRadius x --pcf-scale);
                           // w = the moments filters' parameter: VSM's variance floor (a fraction of m2), the
                           // exponent c of ESM and EVSM, MSM's moment bias (moments_parameter)
  mat4 map_view_proj[4];   // spot / directional lights: one 2D map layer each (backends/common/map_lights.h)
  vec4 map_light[4];       // xyz: spot position, or unit vector towards a directional light; w: 1 spot, 2 dir.
  vec4 map_color[4];       // rgb; w: spot near plane
  vec4 map_range[4];       // x: spot far plane
  vec4 lights_info;        // x: number of map lights; y: 1 when the scene has a point light (a cube); z: the light
                           // the check variant reports; w: the case's point lights (the list's length)
  vec4 moments_knobs;      // the moments filters' tuning (MomentsTuning): x = bleed reduction a (0: none);
                           // y = what z = distance / far is multiplied by before its moments (1, or far: world
                           // units); z = the moments format's unit roundoff (2^-24 float, 2^-11 half)
  vec4 raster_knobs;       // x = --cube / the edge of the pass's target (an atlas tile, a paraboloid's or a
                           // tetrahedron's layer, a cube's face): --raster-perturb's step there (raster_perturb.glsl)
} frame;

// Per draw of the shadow pass: the face a six_pass draw renders, and for vs_layer with face culling the faces
// the object's bounds touch (bit f = face f). Vulkan pushes them; GL binds one of 64 prebuilt ranges (entry k
// holds face k and mask k). Mirrors gpu::PassUniforms.
// mesh_shader's Vulkan draws also push their first task group (GL passes it to glDrawMeshTasksNV instead).
#ifdef VULKAN
layout(push_constant) uniform PassUniforms {
  int face;
  uint face_mask;
#if defined(TECHNIQUE_MESH_SHADER)
  uint first_task;
#endif
} pass;
#else
layout(std140, binding = 1) uniform PassUniforms { int face; uint face_mask; } pass;
#endif

#ifdef POINT_LIGHT_LIST
// The lighting pass shades every point light of the case (CaseConfig::light_count) from this list, one record a
// light in the scene's order, and the shadow lookups read the light being shaded (g_light) through the functions
// below. The shadow pass renders one light at a time from that light's own FrameUniforms (frame.light_*), or,
// with every light in one pass (ALL_LIGHTS), each primitive's light from this list.
// Mirrors gpu::PointLightRecord.
struct PointLightRecord {
  vec4 position_far;  // xyz world units; w = the light's far plane, its range (world units)
  vec4 colour_near;   // rgb; w = near plane
  vec4 moments;       // x = what the moments filters multiply z = distance / far by (moments_knobs.y's per light)
  vec4 atlas_tile;    // layout atlas: xy the light's block's first texel, z its faces' edge, w the border (texels)
  mat4 face_view_proj[6];  // the light's layers' view-projections: the shadow pass with every light in one pass
};
layout(std430, binding = 9) readonly buffer PointLights { PointLightRecord point_lights[]; };
int g_light = 0;  // the light being shaded: its layers in the shadow map, its record above
vec3 light_position() { return point_lights[g_light].position_far.xyz; }
float light_far() { return point_lights[g_light].position_far.w; }
float light_near() { return point_lights[g_light].colour_near.w; }
float moments_distance_scale() { return point_lights[g_light].moments.x; }
#else
vec3 light_position() { return frame.light_position.xyz; }
float light_far() { return frame.light_position.w; }
float light_near() { return frame.light_color.w; }
float moments_distance_scale() { return frame.moments_knobs.y; }
#endif
