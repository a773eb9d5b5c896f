// Dual-paraboloid layout (backends/common/paraboloid.h holds the convention and the same arithmetic in C++: change
// both together). Layer 0 sees z >= 0 from the light with window x = world -X, layer 1 z < 0 with window x = world
// +X; a unit direction d with forward f = a d.z (a = +1, -1) lands at (-a d.x, d.y) / (1 + f) in the unit disk.
// Needs common.glsl (frame: light position, near, far).

// Clip position of world point `p` in `layer`: the paraboloid warp of its direction, depth linear in its distance
// (GL's [-1, 1] or Vulkan's [0, 1]), w = 1 so nothing is divided. The warp is per vertex: a triangle's edges are
// straight in the layer, not the curves the exact map would draw, the layout's error that tessellation reduces.
// `precise`: the same value whichever stage computes it (six_pass in the vertex stage, the GS techniques there).
vec4 paraboloid_clip(int layer, vec3 p, out float forward) {
  precise vec3 v = p - frame.light_position.xyz;
  precise float len = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  // Signs by selection, not by multiplying with +-1: nothing here a compiler could fuse differently per stage.
  float vz = layer == 0 ? v.z : -v.z;
  float vx = layer == 0 ? -v.x : v.x;
  forward = vz;  // >= 0 in the layer's hemisphere: the clip distance that keeps the other one out
  precise float depth = (len - frame.light_color.w) / (light_far() - frame.light_color.w);
#ifdef VULKAN
  float z = depth;
#else
  precise float z = 2.0 * depth - 1.0;
#endif
  precise float denominator = len + vz;
  precise vec2 xy = vec2(vx, v.y) / denominator;
  return vec4(xy, z, 1.0);
}

// (s, t, layer) that direction `dir` reads: the layer its hemisphere selects (z >= 0: layer 0) and the texture
// coordinates of its point in the unit disk.
vec3 paraboloid_coord(vec3 dir) {
  float layer = dir.z >= 0.0 ? 0.0 : 1.0;
  float a = dir.z >= 0.0 ? 1.0 : -1.0;
  float len = length(dir);
  vec2 xy = vec2(-a * dir.x, dir.y) / (len + a * dir.z);
  return vec3(0.5 * xy + 0.5, layer);
}
