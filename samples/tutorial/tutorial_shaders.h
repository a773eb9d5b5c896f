#pragma once
// The point-shadow tutorial's shaders as its chapter gives them (the chapter's text:
// point_shadows_depth.vs/.gs/.fs and point_shadows.vs/.fs), for samples/tutorial only: the harness's own
// shaders live in shaders/. The lighting fragment shader takes one of the chapter's three ShadowCalculation
// bodies (hard, the 64-sample grid, the 20-direction disk with the view-distance radius) and the tutorial's
// diffuse texture or a constant albedo.

#include <string>

namespace tutorial {

inline constexpr const char* kDepthVertex = R"(#version 330 core
layout (location = 0) in vec3 aPos;
uniform mat4 model;
void main() { gl_Position = model * vec4(aPos, 1.0); }
)";

inline constexpr const char* kDepthGeometry = R"(#version 330 core
layout (triangles) in;
layout (triangle_strip, max_vertices = 18) out;
uniform mat4 shadowMatrices[6];
out vec4 FragPos;
void main() {
  for (int face = 0; face < 6; ++face) {
    gl_Layer = face;
    for (int i = 0; i < 3; ++i) {
      FragPos = gl_in[i].gl_Position;
      gl_Position = shadowMatrices[face] * FragPos;
      EmitVertex();
    }
    EndPrimitive();
  }
}
)";

inline constexpr const char* kDepthFragment = R"(#version 330 core
in vec4 FragPos;
uniform vec3 lightPos;
uniform float far_plane;
void main() { gl_FragDepth = length(FragPos.xyz - lightPos) / far_plane; }
)";

inline constexpr const char* kLightingVertex = R"(#version 330 core
layout (location = 0) in vec3 aPos;
layout (location = 1) in vec3 aNormal;
layout (location = 2) in vec2 aTexCoords;
out VS_OUT { vec3 FragPos; vec3 Normal; vec2 TexCoords; } vs_out;
uniform mat4 projection;
uniform mat4 view;
uniform mat4 model;
uniform bool reverse_normals;
void main() {
  vs_out.FragPos = vec3(model * vec4(aPos, 1.0));
  if (reverse_normals) vs_out.Normal = transpose(inverse(mat3(model))) * (-1.0 * aNormal);
  else vs_out.Normal = transpose(inverse(mat3(model))) * aNormal;
  vs_out.TexCoords = aTexCoords;
  gl_Position = projection * view * model * vec4(aPos, 1.0);
}
)";

inline constexpr const char* kLightingFragmentBody = R"(
out vec4 FragColor;
in VS_OUT { vec3 FragPos; vec3 Normal; vec2 TexCoords; } fs_in;
uniform sampler2D diffuseTexture;
uniform samplerCube depthMap;
uniform vec3 lightPos;
uniform vec3 viewPos;
uniform float far_plane;

vec3 sampleOffsetDirections[20] = vec3[](
  vec3( 1,  1,  1), vec3( 1, -1,  1), vec3(-1, -1,  1), vec3(-1,  1,  1),
  vec3( 1,  1, -1), vec3( 1, -1, -1), vec3(-1, -1, -1), vec3(-1,  1, -1),
  vec3( 1,  1,  0), vec3( 1, -1,  0), vec3(-1, -1,  0), vec3(-1,  1,  0),
  vec3( 1,  0,  1), vec3(-1,  0,  1), vec3( 1,  0, -1), vec3(-1,  0, -1),
  vec3( 0,  1,  1), vec3( 0, -1,  1), vec3( 0, -1, -1), vec3( 0,  1, -1));

float ShadowCalculation(vec3 fragPos) {
  vec3 fragToLight = fragPos - lightPos;
  float currentDepth = length(fragToLight);
  float shadow = 0.0;
#if defined(FILTER_HARD)
  float closestDepth = texture(depthMap, fragToLight).r * far_plane;
  float bias = 0.05;
  shadow = currentDepth - bias > closestDepth ? 1.0 : 0.0;
#elif defined(FILTER_GRID64)
  float bias = 0.05;
  float samples = 4.0;
  float offset = 0.1;
  for (float x = -offset; x < offset; x += offset / (samples * 0.5))
    for (float y = -offset; y < offset; y += offset / (samples * 0.5))
      for (float z = -offset; z < offset; z += offset / (samples * 0.5)) {
        float closestDepth = texture(depthMap, fragToLight + vec3(x, y, z)).r * far_plane;
        if (currentDepth - bias > closestDepth) shadow += 1.0;
      }
  shadow /= (samples * samples * samples);
#else
  float bias = 0.15;
  int samples = 20;
  float viewDistance = length(viewPos - fragPos);
  float diskRadius = (1.0 + (viewDistance / far_plane)) / 25.0;
  for (int i = 0; i < samples; ++i) {
    float closestDepth = texture(depthMap, fragToLight + sampleOffsetDirections[i] * diskRadius).r * far_plane;
    if (currentDepth - bias > closestDepth) shadow += 1.0;
  }
  shadow /= float(samples);
#endif
  return shadow;
}

void main() {
#if defined(ALBEDO_TEXTURE)
  vec3 color = texture(diffuseTexture, fs_in.TexCoords).rgb;
#else
  vec3 color = vec3(0.76, 0.70, 0.62);
#endif
  vec3 normal = normalize(fs_in.Normal);
  vec3 lightColor = vec3(0.3);
  vec3 ambient = 0.3 * color;
  vec3 lightDir = normalize(lightPos - fs_in.FragPos);
  float diff = max(dot(lightDir, normal), 0.0);
  vec3 diffuse = diff * lightColor;
  vec3 viewDir = normalize(viewPos - fs_in.FragPos);
  vec3 halfwayDir = normalize(lightDir + viewDir);
  float spec = pow(max(dot(normal, halfwayDir), 0.0), 64.0);
  vec3 specular = spec * lightColor;
  float shadow = ShadowCalculation(fs_in.FragPos);
  vec3 lighting = (ambient + (1.0 - shadow) * (diffuse + specular)) * color;
  FragColor = vec4(lighting, 1.0);
}
)";

inline std::string lighting_fragment(const std::string& filter, const std::string& albedo) {
  const char* define = filter == "hard"         ? "FILTER_HARD"
                       : filter == "pcf_grid64" ? "FILTER_GRID64"
                                                : "FILTER_DISK20";
  return std::string("#version 330 core\n#define ") + define + "\n" +
         (albedo == "texture" ? "#define ALBEDO_TEXTURE\n" : "") + kLightingFragmentBody;
}

}  // namespace tutorial
