// Integer cube-texel addressing for the moments blur: a texel's neighbour k steps along a face axis, continued
// onto the adjacent face where it runs past an edge. backends/common/cube_faces.cpp (cube::neighbour_texel) is
// the same arithmetic in C++, which the moments check replays; both follow the API's cube-map table (Table 8.19,
// face order +X, -X, +Y, -Y, +Z, -Z).
//
// A texel centre as a point on a cube of half-extent `size`, in half-texel units: the face's major axis is
// +-size and its s and t coordinates become u = 2s + 1 - size and v = 2t + 1 - size, placed as the table places
// sc and tc. Integers keep the addressing exact on every device, so host and device pick the same texels.
ivec3 texel_point(int face, int s, int t, int size) {
  int u = 2 * s + 1 - size, v = 2 * t + 1 - size;
  if (face == 0) return ivec3(size, -v, -u);   // +X: sc = -z, tc = -y
  if (face == 1) return ivec3(-size, -v, u);   // -X: sc = +z, tc = -y
  if (face == 2) return ivec3(u, size, v);     // +Y: sc = +x, tc = +z
  if (face == 3) return ivec3(u, -size, -v);   // -Y: sc = +x, tc = -z
  if (face == 4) return ivec3(u, -v, size);    // +Z: sc = +x, tc = -y
  return ivec3(-u, -v, -size);                 // -Z: sc = -x, tc = -y
}

// The texel (s, t, face) k steps from (s, t) of `face` along its s (axis 0) or t (axis 1). Past the edge, the
// step continues on the adjacent face as on the unfolded cube: the coordinate that left the face becomes that
// face's major axis and the old major axis shrinks by the excess. Needs |k| <= size (one seam per step).
ivec3 neighbour_texel(int face, int s, int t, int axis, int k, int size) {
  if (axis == 0) s += k; else t += k;
  if (s >= 0 && s < size && t >= 0 && t < size) return ivec3(s, t, face);
  ivec3 p = texel_point(face, s, t, size);
  const int major = face / 2;
  int beyond = major == 0 ? 1 : 0;
  for (int c = 0; c < 3; ++c)
    if (c != major && abs(p[c]) > size) beyond = c;
  const int excess = abs(p[beyond]) - size;
  p[major] = (p[major] > 0 ? 1 : -1) * (size - excess);
  p[beyond] = p[beyond] > 0 ? size : -size;
  const int to = 2 * beyond + (p[beyond] > 0 ? 0 : 1);
  int sc, tc;
  if (to == 0) { sc = -p.z; tc = -p.y; }
  else if (to == 1) { sc = p.z; tc = -p.y; }
  else if (to == 2) { sc = p.x; tc = p.z; }
  else if (to == 3) { sc = p.x; tc = -p.z; }
  else if (to == 4) { sc = p.x; tc = -p.y; }
  else { sc = -p.x; tc = -p.y; }
  return ivec3((sc + size - 1) / 2, (tc + size - 1) / 2, to);
}
