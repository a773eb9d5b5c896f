#version 450
// Layered single pass: each triangle is sent to the six faces through gl_Layer.
#include "common.glsl"

#if defined(GS_INSTANCED)
layout(triangles, invocations = 6) in;      // one invocation per face
layout(triangle_strip, max_vertices = 3) out;
#else
layout(triangles) in;                        // seed 000: one invocation loops over the faces
layout(triangle_strip, max_vertices = 18) out;
#endif

layout(location = 0) out vec3 world_position;

void emit_face(int face) {
  for (int i = 0; i < 3; ++i) {
    gl_Layer = face;  // per vertex: outputs are undefined after EmitVertex
    world_position = gl_in[i].gl_Position.xyz;
    gl_Position = frame.face_view_proj[face] * gl_in[i].gl_Position;
    EmitVertex();
  }
  EndPrimitive();
}

void main() {
#if defined(GS_INSTANCED)
  emit_face(gl_InvocationID);
#else
  for (int face = 0; face < 6; ++face) emit_face(face);
#endif
}
