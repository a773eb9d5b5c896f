// The point-shadow tutorial's sample, rendered the way the tutorial renders it (the point-shadow tutorial:
// depth cube map filled in one geometry-shader pass storing distance / far_plane, then the room lit into the
// window's framebuffer: one RGBA8 colour buffer and a 24-bit depth buffer, both cleared each frame, one
// program with the tutorial's shaders and its wood texture), headless. It exists to hold the harness's timed
// frame against an independent renderer of the same scene: scripts/experiments/tutorial_ab.py runs both
// alternately. Not part of the product's checks.
//
// Usage: omnishadow_tutorial_sample [--filter hard|pcf_grid64|pcf_disk20] [--albedo texture|constant]
//                                   [--depth-format d32f|d24|unsized] [--cube 1024] [--size 800x600]
//                                   [--camera-depth d24s8|d32f] [--frames 30] [--warmup 5] [--png FILE]
// --depth-format: the cube's depth format, d32f by default as the harness's (the tutorial's unsized
// GL_DEPTH_COMPONENT is 24-bit on NVIDIA: a different format costs differently, so A/B runs name one).
// --camera-depth: the window's depth buffer, d24s8 by default (GLFW's default framebuffer); d32f is the
// harness's lighting target's (gl_targets.cpp), to tell a difference in the lighting pass's cost by that
// format alone. Prints one JSON object: per pass the median wall time from the first command to glFinish (as
// the harness times its passes) and the median GPU time (GL_TIME_ELAPSED around the pass), in milliseconds.

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/gl/egl_context.h"
#include "bench/io/image_io.h"
#include "samples/tutorial/tutorial_shaders.h"

namespace {

struct Options {
  std::string filter = "hard", albedo = "texture", png;  // png: write the last frame there (to look at it)
  std::string depth_format = "d32f";
  std::string camera_depth = "d24s8";
  int cube = 1024, width = 800, height = 600, frames = 30, warmup = 5;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument("option " + arg + " needs a value");
    const std::string value = argv[++i];
    if (arg == "--filter")
      o.filter = value;
    else if (arg == "--albedo")
      o.albedo = value;
    else if (arg == "--depth-format")
      o.depth_format = value;
    else if (arg == "--camera-depth")
      o.camera_depth = value;
    else if (arg == "--png")
      o.png = value;
    else if (arg == "--cube")
      o.cube = std::stoi(value);
    else if (arg == "--frames")
      o.frames = std::stoi(value);
    else if (arg == "--warmup")
      o.warmup = std::stoi(value);
    else if (arg == "--size" && std::sscanf(value.c_str(), "%dx%d", &o.width, &o.height) == 2)
      continue;
    else
      throw std::invalid_argument("unknown option or bad value: " + arg + " " + value);
  }
  if (o.filter != "hard" && o.filter != "pcf_grid64" && o.filter != "pcf_disk20")
    throw std::invalid_argument("--filter: hard, pcf_grid64 or pcf_disk20, not " + o.filter);
  if (o.albedo != "texture" && o.albedo != "constant")
    throw std::invalid_argument("--albedo: texture or constant");
  if (o.camera_depth != "d24s8" && o.camera_depth != "d32f")
    throw std::invalid_argument("--camera-depth: d24s8 or d32f, not " + o.camera_depth);
  if (o.depth_format != "d32f" && o.depth_format != "d24" && o.depth_format != "unsized")
    throw std::invalid_argument("--depth-format: d32f, d24 or unsized, not " + o.depth_format);
  if (o.cube < 1 || o.frames < 1 || o.warmup < 0 || o.width < 1 || o.height < 1)
    throw std::invalid_argument("--cube, --frames, --size must be positive");
  return o;
}

GLuint compile(GLenum stage, const std::string& source) {
  GLuint s = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("tutorial shader: ") + log);
  }
  return s;
}

GLuint link(const std::vector<std::pair<GLenum, std::string>>& stages) {
  GLuint p = glCreateProgram();
  for (const auto& [stage, source] : stages) glAttachShader(p, compile(stage, source));
  glLinkProgram(p);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("tutorial program does not link");
  return p;
}

// The tutorial's unit cube: 36 vertices of position, outward normal and texture coordinates,
// counter-clockwise from outside. Generated per face rather than listed.
GLuint cube_vao() {
  std::vector<float> v;
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      glm::vec3 n(0.0f), u(0.0f), w(0.0f);
      n[axis] = sign;
      u[(axis + 1) % 3] = 1.0f;
      w[(axis + 2) % 3] = sign;  // u x w = n: counter-clockwise seen from outside
      const glm::vec2 corners[6] = {{-1, -1}, {1, -1}, {1, 1}, {1, 1}, {-1, 1}, {-1, -1}};
      for (const glm::vec2& c : corners) {
        const glm::vec3 p = n + c.x * u + c.y * w;
        v.insert(v.end(), {p.x, p.y, p.z, n.x, n.y, n.z, 0.5f * (c.x + 1.0f), 0.5f * (c.y + 1.0f)});
      }
    }
  GLuint vao = 0, vbo = 0;
  glGenVertexArrays(1, &vao);
  glGenBuffers(1, &vbo);
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 8 * sizeof(float),
                          reinterpret_cast<void*>(uintptr_t(a * 3 * sizeof(float))));
  }
  return vao;
}

// Stands in for the tutorial's wood.png: a 512 x 512 RGBA8 texture of stripes with mipmaps, sampled as the
// tutorial's loadTexture sets it up (repeat, trilinear).
GLuint wood_texture() {
  const int n = 512;
  std::vector<unsigned char> texels(size_t(n) * n * 4);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const float grain = 0.5f + 0.5f * std::sin(0.11f * float(x) + 3.0f * std::sin(0.02f * float(y)));
      unsigned char* t = &texels[(size_t(y) * n + x) * 4];
      t[0] = static_cast<unsigned char>(120 + 80 * grain), t[1] = static_cast<unsigned char>(80 + 50 * grain);
      t[2] = static_cast<unsigned char>(40 + 20 * grain), t[3] = 255;
    }
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, n, n, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return tex;
}

// The tutorial's renderScene: the room (a cube scaled 5, seen from inside: culling off, normals reversed) and
// five cubes. `program` takes a `model` matrix and the `reverse_normals` flag.
void render_scene(GLuint program, GLuint vao) {
  const GLint model = glGetUniformLocation(program, "model"),
              reverse = glGetUniformLocation(program, "reverse_normals");
  glBindVertexArray(vao);
  auto draw = [&](const glm::mat4& m) {
    glUniformMatrix4fv(model, 1, GL_FALSE, glm::value_ptr(m));
    glDrawArrays(GL_TRIANGLES, 0, 36);
  };
  glDisable(GL_CULL_FACE);
  glUniform1i(reverse, 1);
  draw(glm::scale(glm::mat4(1.0f), glm::vec3(5.0f)));
  glUniform1i(reverse, 0);
  glEnable(GL_CULL_FACE);
  auto placed = [](glm::vec3 t, float s) {
    return glm::scale(glm::translate(glm::mat4(1.0f), t), glm::vec3(s));
  };
  draw(placed({4.0f, -3.5f, 0.0f}, 0.5f));
  draw(placed({2.0f, 3.0f, 1.0f}, 0.75f));
  draw(placed({-3.0f, -1.0f, 0.0f}, 0.5f));
  draw(placed({-1.5f, 1.0f, 1.5f}, 0.5f));
  glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(-1.5f, 2.0f, -3.0f));
  m = glm::rotate(m, glm::radians(60.0f), glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f)));
  draw(glm::scale(m, glm::vec3(0.75f)));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The depth cube map and its framebuffer, as the tutorial makes them; returns the framebuffer.
GLuint depth_cube_framebuffer(int size, const std::string& format, GLuint& depth_cube) {
  glGenTextures(1, &depth_cube);
  glBindTexture(GL_TEXTURE_CUBE_MAP, depth_cube);
  const GLint internal = format == "d32f"  ? GL_DEPTH_COMPONENT32F
                         : format == "d24" ? GL_DEPTH_COMPONENT24
                                           : GL_DEPTH_COMPONENT;
  for (GLenum f = 0; f < 6; ++f)
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, internal, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                 nullptr);
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER})
    glTexParameteri(GL_TEXTURE_CUBE_MAP, p, GL_NEAREST);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(GL_TEXTURE_CUBE_MAP, p, GL_CLAMP_TO_EDGE);
  GLuint fbo = 0;
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depth_cube, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  return fbo;
}

// The window's framebuffer, headless: RGBA8 colour and 24-bit depth with stencil (GLFW's default), or D32F.
GLuint window_framebuffer(int width, int height, bool d32f) {
  GLuint fbo = 0, buffers[2] = {};
  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(2, buffers);
  glBindRenderbuffer(GL_RENDERBUFFER, buffers[0]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, buffers[1]);
  glRenderbufferStorage(GL_RENDERBUFFER, d32f ? GL_DEPTH_COMPONENT32F : GL_DEPTH24_STENCIL8, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, d32f ? GL_DEPTH_ATTACHMENT : GL_DEPTH_STENCIL_ATTACHMENT,
                            GL_RENDERBUFFER, buffers[1]);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("the headless window framebuffer is incomplete");
  return fbo;
}

// One frame of the tutorial's render loop, its two passes timed apart.
class TutorialRenderer {
 public:
  explicit TutorialRenderer(const Options& o)
      : o_(o),
        depth_program_(link({{GL_VERTEX_SHADER, tutorial::kDepthVertex},
                             {GL_GEOMETRY_SHADER, tutorial::kDepthGeometry},
                             {GL_FRAGMENT_SHADER, tutorial::kDepthFragment}})),
        light_program_(link({{GL_VERTEX_SHADER, tutorial::kLightingVertex},
                             {GL_FRAGMENT_SHADER, tutorial::lighting_fragment(o.filter, o.albedo)}})),
        vao_(cube_vao()),
        wood_(wood_texture()),
        depth_fbo_(depth_cube_framebuffer(o.cube, o.depth_format, depth_cube_)),
        window_fbo_(window_framebuffer(o.width, o.height, o.camera_depth == "d32f")) {
    glEnable(GL_DEPTH_TEST);
    const glm::mat4 shadow_proj = glm::perspective(glm::radians(90.0f), 1.0f, kNear, kFar);
    const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    for (int f = 0; f < 6; ++f)
      shadow_matrices_[size_t(f)] = shadow_proj * glm::lookAt(kLight, kLight + dirs[f], ups[f]);
    projection_ = glm::perspective(glm::radians(45.0f), float(o.width) / float(o.height), 0.1f, 100.0f);
    view_ = glm::lookAt(kCamera, kCamera + glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
  }

  // Each pass inside a GL_TIME_ELAPSED query, as the harness times its passes (GPU time beside the wall
  // time); read after the pass's glFinish, when the result is available without a wait.
  void shadow_pass() {
    glBeginQuery(GL_TIME_ELAPSED, queries_[0]);
    glViewport(0, 0, o_.cube, o_.cube);
    glBindFramebuffer(GL_FRAMEBUFFER, depth_fbo_);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth_program_);
    for (int f = 0; f < 6; ++f)
      glUniformMatrix4fv(uniform(depth_program_, "shadowMatrices[" + std::to_string(f) + "]"), 1, GL_FALSE,
                         glm::value_ptr(shadow_matrices_[size_t(f)]));
    glUniform1f(uniform(depth_program_, "far_plane"), kFar);
    glUniform3fv(uniform(depth_program_, "lightPos"), 1, glm::value_ptr(kLight));
    render_scene(depth_program_, vao_);
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
  }

  void lighting_pass() {
    glBeginQuery(GL_TIME_ELAPSED, queries_[1]);
    glViewport(0, 0, o_.width, o_.height);
    glBindFramebuffer(GL_FRAMEBUFFER, window_fbo_);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(light_program_);
    glUniformMatrix4fv(uniform(light_program_, "projection"), 1, GL_FALSE, glm::value_ptr(projection_));
    glUniformMatrix4fv(uniform(light_program_, "view"), 1, GL_FALSE, glm::value_ptr(view_));
    glUniform3fv(uniform(light_program_, "lightPos"), 1, glm::value_ptr(kLight));
    glUniform3fv(uniform(light_program_, "viewPos"), 1, glm::value_ptr(kCamera));
    glUniform1f(uniform(light_program_, "far_plane"), kFar);
    glUniform1i(uniform(light_program_, "diffuseTexture"), 0);
    glUniform1i(uniform(light_program_, "depthMap"), 1);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, wood_);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_CUBE_MAP, depth_cube_);
    render_scene(light_program_, vao_);
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
  }

  // The GPU time of the latest shadow (0) or lighting (1) pass, ms.
  double gpu_ms(int pass) const {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(queries_[pass], GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-6;
  }

  void write_png(const std::string& path) const {
    std::vector<uint8_t> rgba(size_t(o_.width) * size_t(o_.height) * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, window_fbo_);
    glReadPixels(0, 0, o_.width, o_.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    omnishadow::bench::write_png_rgba_bottom_up(path, o_.width, o_.height, rgba);
  }

 private:
  // The scene's light at frame 0 (the origin), the tutorial's camera and light planes.
  static constexpr glm::vec3 kLight{0.0f, 0.0f, 0.0f}, kCamera{0.0f, 0.0f, 3.0f};
  static constexpr float kNear = 1.0f, kFar = 25.0f;
  static GLint uniform(GLuint program, const std::string& name) {
    return glGetUniformLocation(program, name.c_str());
  }

  const Options& o_;
  GLuint depth_program_, light_program_, vao_, wood_, depth_cube_ = 0, depth_fbo_, window_fbo_;
  std::array<GLuint, 2> queries_ = make_queries();
  static std::array<GLuint, 2> make_queries() {
    std::array<GLuint, 2> q{};
    glGenQueries(2, q.data());
    return q;
  }
  std::array<glm::mat4, 6> shadow_matrices_{};
  glm::mat4 projection_{1.0f}, view_{1.0f};
};

int run(const Options& o) {
  omnishadow::gl::EglContext context("surfaceless", 0, false);
  TutorialRenderer renderer(o);
  using clock = std::chrono::steady_clock;
  auto ms = [](clock::time_point a, clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  std::vector<double> shadow_ms, lighting_ms, shadow_gpu_ms, lighting_gpu_ms;
  for (int frame = 0; frame < o.warmup + o.frames; ++frame) {
    const auto t0 = clock::now();
    renderer.shadow_pass();
    const auto t1 = clock::now();
    renderer.lighting_pass();
    const auto t2 = clock::now();
    if (frame < o.warmup) continue;
    shadow_ms.push_back(ms(t0, t1));
    lighting_ms.push_back(ms(t1, t2));
    shadow_gpu_ms.push_back(renderer.gpu_ms(0));
    lighting_gpu_ms.push_back(renderer.gpu_ms(1));
  }
  if (!o.png.empty()) renderer.write_png(o.png);
  if (GLenum e = glGetError(); e != GL_NO_ERROR) throw std::runtime_error("GL error " + std::to_string(e));
  std::printf(
      "{\"filter\": \"%s\", \"albedo\": \"%s\", \"depth_format\": \"%s\", \"cube\": %d, \"size\": [%d, %d], "
      "\"frames\": %d, \"shadow_ms\": %.4f, \"lighting_ms\": %.4f, \"shadow_gpu_ms\": %.4f, "
      "\"lighting_gpu_ms\": %.4f, \"renderer\": \"%s\"}\n",
      o.filter.c_str(), o.albedo.c_str(), o.depth_format.c_str(), o.cube, o.width, o.height, o.frames,
      median(shadow_ms), median(lighting_ms), median(shadow_gpu_ms), median(lighting_gpu_ms),
      reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "omnishadow_tutorial_sample: %s\n", e.what());
    return 2;
  }
}
