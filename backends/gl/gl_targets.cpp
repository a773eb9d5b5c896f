#include "backends/gl/gl_targets.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "backends/common/storage_filter_tables.h"

namespace omnishadow::gl {
namespace {

std::string hex(GLenum value) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04x", value);
  return buf;
}

void check_allocation(const char* what) {
  GLenum error = glGetError();
  if (error == GL_OUT_OF_MEMORY) throw std::runtime_error(std::string("GL_OUT_OF_MEMORY allocating ") + what);
  if (error != GL_NO_ERROR) throw std::runtime_error("GL error " + hex(error) + " allocating " + what);
}

void check_complete(GLuint fbo, const char* what) {
  GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string(what) + " framebuffer incomplete (status " + hex(status) + ")");
}

// NEAREST and clamp as in the point-shadow tutorial; the hw_compare2x2 filter overrides filtering with a
// sampler object.
void cube_parameters(GLuint tex) {
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

GLuint create_cube(GLenum internal_format, int size) {
  GLuint tex = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &tex);
  glTextureStorage2D(tex, 1, internal_format, size, size);
  cube_parameters(tex);
  return tex;
}

// `count` layers of a 2D array (what multiview, several lights and the layouts that are no cube render into)
// and the view of them that is sampled: a cube map (six layers, layer f face f), a cube-map array (layer 6k +
// f face f of cube k), or, for a layout that is no cube, the array itself.
GLuint create_layer_array(GLenum internal_format, int size, int count, GLenum sampled_target, GLuint& view) {
  GLuint array = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
  glTextureStorage3D(array, 1, internal_format, size, size, count);
  if (sampled_target == GL_TEXTURE_2D_ARRAY) {
    cube_parameters(array);
    view = array;
    return array;
  }
  glGenTextures(1, &view);  // a view needs a name never bound (glCreateTextures would give it a target)
  glTextureView(view, sampled_target, array, internal_format, 0, 1, 0, static_cast<GLuint>(count));
  cube_parameters(view);
  return array;
}

// A 2D-array view of `count` layers of `texture` from `first`.
GLuint layer_view(GLuint texture, GLenum format, int first, int count) {
  GLuint view = 0;
  glGenTextures(1, &view);
  glTextureView(view, GL_TEXTURE_2D_ARRAY, texture, format, 0, 1, static_cast<GLuint>(first),
                static_cast<GLuint>(count));
  return view;
}

GLuint create_2d(GLenum internal_format, int width, int height) {
  GLuint tex = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  glTextureStorage2D(tex, 1, internal_format, width, height);
  return tex;
}

}  // namespace

GLenum depth_internal_format(DepthFormat format) {
  switch (format) {
    case DepthFormat::d16:
      return GL_DEPTH_COMPONENT16;
    case DepthFormat::d24:
      return GL_DEPTH_COMPONENT24;
    case DepthFormat::d32f:
      return GL_DEPTH_COMPONENT32F;
  }
  return GL_DEPTH_COMPONENT32F;
}

GLenum colour_internal_format(ColourFormat format) {
  switch (format) {
    case ColourFormat::r32f:
      return GL_R32F;
    case ColourFormat::rg32f:
      return GL_RG32F;
    case ColourFormat::rg16f:
      return GL_RG16F;
    case ColourFormat::r16f:
      return GL_R16F;
    case ColourFormat::rgba32f:
      return GL_RGBA32F;
    case ColourFormat::rgba16f:
      return GL_RGBA16F;
    case ColourFormat::none:
      break;
  }
  return GL_NONE;
}

// The framebuffers of a shadow target: one per light and layer (six_pass) and one per light over its layers.
static void create_shadow_framebuffers(ShadowTargets& t, bool arrays, const ShadowShape& shape,
                                       GLenum depth_format, GLenum colour_format) {
  const int layers = t.layers;
  const bool multiview = shape.multiview, has_colour = colour_format != GL_NONE;
  const GLuint depth_target = arrays ? t.depth_array : t.depth;
  const GLuint colour_target = arrays ? t.colour_array : t.colour;

  // A layered texture attached whole gives a layered framebuffer, one layer (glNamedFramebufferTextureLayer)
  // the per-face framebuffer of six_pass. A light's layers of a shared array are attached whole through a
  // view of them. With multiview the light's layers are its six views instead (GL_OVR_multiview has no
  // named-framebuffer form).
  auto attach_light = [&](GLuint fbo, GLenum attachment, GLuint texture, GLenum format, int light) {
    if (multiview) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
      glFramebufferTextureMultiviewOVR(GL_DRAW_FRAMEBUFFER, attachment, texture, 0, light * layers, 6);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
      return;
    }
    if (t.lights > 1) {
      texture = layer_view(texture, format, light * layers, layers);
      t.views.push_back(texture);
    }
    glNamedFramebufferTexture(fbo, attachment, texture, 0);
  };
  auto attach = [&](GLuint fbo, int light, int layer) {
    if (layer < 0)
      attach_light(fbo, GL_DEPTH_ATTACHMENT, depth_target, depth_format, light);
    else
      glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, depth_target, 0, light * layers + layer);
    if (has_colour) {
      if (layer < 0)
        attach_light(fbo, GL_COLOR_ATTACHMENT0, colour_target, colour_format, light);
      else
        glNamedFramebufferTextureLayer(fbo, GL_COLOR_ATTACHMENT0, colour_target, 0, light * layers + layer);
      glNamedFramebufferDrawBuffer(fbo, GL_COLOR_ATTACHMENT0);
    } else {
      glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    }
    glNamedFramebufferReadBuffer(fbo, GL_NONE);
  };
  t.face_fbos.resize(static_cast<size_t>(layers * t.lights));
  t.layered_fbos.resize(static_cast<size_t>(t.lights));
  glCreateFramebuffers(layers * t.lights, t.face_fbos.data());
  glCreateFramebuffers(t.lights, t.layered_fbos.data());
  for (int k = 0; k < t.lights; ++k) {
    for (int f = 0; f < layers; ++f) {
      attach(t.face_fbos[size_t(k * layers + f)], k, f);
      check_complete(t.face_fbos[size_t(k * layers + f)], "per-face shadow");
    }
    attach(t.layered_fbos[size_t(k)], k, -1);
    check_complete(t.layered_fbos[size_t(k)], multiview ? "multiview shadow" : "layered shadow");
  }
  t.all_lights_fbo = t.layered_fbos[0];
  if (t.lights == 1 || multiview) return;
  glCreateFramebuffers(1, &t.all_lights_fbo);  // the arrays attached whole: every light's layers
  glNamedFramebufferTexture(t.all_lights_fbo, GL_DEPTH_ATTACHMENT, depth_target, 0);
  if (has_colour) glNamedFramebufferTexture(t.all_lights_fbo, GL_COLOR_ATTACHMENT0, colour_target, 0);
  glNamedFramebufferDrawBuffer(t.all_lights_fbo, has_colour ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  glNamedFramebufferReadBuffer(t.all_lights_fbo, GL_NONE);
  check_complete(t.all_lights_fbo, "every light's layered shadow");
}

// Layout atlas: one layer of the plan's size, depth (and colour) sampled as a 2D array of that layer, one
// framebuffer over it.
static ShadowTargets create_atlas_targets(const ShadowShape& shape) {
  ShadowTargets t;
  t.storage = shape.storage;
  t.size = shape.size;
  t.layers = 6;
  t.lights = shape.lights;
  t.atlas = shape.atlas;
  const int width = shape.atlas->width, height = shape.atlas->height;
  auto layer = [&](GLenum format) {
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &tex);
    glTextureStorage3D(tex, 1, format, width, height, 1);
    cube_parameters(tex);
    return tex;
  };
  const GLenum depth_internal = depth_internal_format(shape.depth_format);
  const GLenum colour_internal =
      colour_internal_format(omnishadow::colour_format(shape.storage, shape.depth_format));
  t.depth = t.depth_array = layer(depth_internal);
  if (colour_internal != GL_NONE) t.colour = t.colour_array = layer(colour_internal);
  t.stored = t.stored_array = t.stored_layers = traits(shape.storage).colour_checked ? t.colour : t.depth;
  t.sampled = t.sampled_layers = t.stored;
  if (traits(shape.storage).moments != MomentKind::none) {  // the blur's images: the layer and one beside it
    t.sampled = t.sampled_layers = t.colour_layers = t.colour;
    t.colour_format = colour_internal;
    t.blur_layers = layer(colour_internal);
  }
  check_allocation("the shadow atlas");
  GLuint fbo = 0;
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, t.depth, 0, 0);
  if (t.colour) glNamedFramebufferTextureLayer(fbo, GL_COLOR_ATTACHMENT0, t.colour, 0, 0);
  glNamedFramebufferDrawBuffer(fbo, t.colour ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  glNamedFramebufferReadBuffer(fbo, GL_NONE);
  check_complete(fbo, "shadow atlas");
  t.layered_fbos = {fbo};
  t.all_lights_fbo = fbo;
  return t;
}

ShadowTargets create_shadow_targets(const ShadowShape& shape) {
  if (shape.atlas) return create_atlas_targets(shape);
  ShadowTargets t;
  t.storage = shape.storage;
  t.size = shape.size;
  t.layers = shape.layers;
  t.lights = shape.lights;
  const int size = shape.size, layers = shape.layers, count = layers * shape.lights;
  const Storage storage = shape.storage;
  // Rendered into 2D arrays (and sampled through views of them) unless one cube map does.
  const bool arrays = shape.multiview || layers != 6 || shape.lights > 1 || shape.cube_array;
  const GLenum sampled_target = shape.cube_array                   ? GL_TEXTURE_CUBE_MAP_ARRAY
                                : layers == 6 && shape.lights == 1 ? GL_TEXTURE_CUBE_MAP
                                                                   : GL_TEXTURE_2D_ARRAY;
  const ColourFormat colour_format = omnishadow::colour_format(storage, shape.depth_format);
  const GLenum colour_internal = colour_internal_format(colour_format);
  const GLenum depth_internal = depth_internal_format(shape.depth_format);
  const bool has_colour = colour_format != ColourFormat::none;
  if (arrays) {
    t.depth_array = create_layer_array(depth_internal, size, count, sampled_target, t.depth);
    if (has_colour)
      t.colour_array = create_layer_array(colour_internal, size, count, sampled_target, t.colour);
  } else {
    t.depth = create_cube(depth_internal, size);
    if (has_colour) t.colour = create_cube(colour_internal, size);
  }
  const bool colour_checked = traits(storage).colour_checked;
  t.stored = colour_checked ? t.colour : t.depth;
  t.stored_array = colour_checked ? t.colour_array : t.depth_array;
  t.sampled = traits(storage).moments != MomentKind::none ? t.colour : t.stored;
  // 2D array views for the compute passes (a cube sampler has no texelFetch; image units bind layers).
  auto layers_of = [&](GLuint cube, GLuint array, GLenum format) {
    return arrays ? array : layer_view(cube, format, 0, 6);
  };
  const GLenum stored_format = colour_checked ? colour_internal : depth_internal;
  t.stored_layers = layers_of(t.stored, t.stored_array, stored_format);
  for (int k = 0; k < t.lights; ++k) {
    if (t.lights == 1) {
      t.light_stored_layers.push_back(t.stored_layers);
      break;
    }
    t.views.push_back(layer_view(t.stored_array, stored_format, k * layers, layers));
    t.light_stored_layers.push_back(t.views.back());
  }
  if (traits(storage).moments != MomentKind::none) {
    t.colour_format = colour_internal;
    t.colour_layers = layers_of(t.colour, t.colour_array, colour_internal);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t.blur_layers);  // the blur's first pass writes here
    glTextureStorage3D(t.blur_layers, 1, colour_internal, size, size, count);
  }
  t.sampled_layers = traits(storage).moments != MomentKind::none ? t.colour_layers : t.stored_layers;
  const bool moments = traits(storage).moments != MomentKind::none;
  for (int k = 0; shape.light_cubes && k < t.lights; ++k) {  // views, not copies: the texels the pass wrote
    GLuint cube = 0;
    glGenTextures(1, &cube);  // a view needs a name never bound
    glTextureView(cube, GL_TEXTURE_CUBE_MAP, moments ? t.colour_array : t.stored_array,
                  moments ? colour_internal : stored_format, 0, 1, GLuint(k * layers), 6);
    cube_parameters(cube);
    t.light_cubes.push_back(cube);
  }
  check_allocation("the shadow maps");
  create_shadow_framebuffers(t, arrays, shape, depth_internal, has_colour ? colour_internal : GL_NONE);
  return t;
}

void destroy(ShadowTargets& t) {
  glDeleteFramebuffers(static_cast<GLsizei>(t.face_fbos.size()), t.face_fbos.data());
  if (!t.layered_fbos.empty() && t.all_lights_fbo != t.layered_fbos[0])
    glDeleteFramebuffers(1, &t.all_lights_fbo);
  glDeleteFramebuffers(static_cast<GLsizei>(t.layered_fbos.size()), t.layered_fbos.data());
  glDeleteTextures(static_cast<GLsizei>(t.views.size()), t.views.data());
  glDeleteTextures(static_cast<GLsizei>(t.light_cubes.size()), t.light_cubes.data());
  // Views first (multiview's layers are the arrays themselves); zero names are ignored.
  if (t.stored_layers != t.stored_array) glDeleteTextures(1, &t.stored_layers);
  if (t.colour_layers != t.colour_array) glDeleteTextures(1, &t.colour_layers);
  // Without cube views (layers != 6) depth and colour are the arrays: each name deleted once.
  const GLuint textures[] = {t.blur_layers, t.colour != t.colour_array ? t.colour : 0u,
                             t.depth != t.depth_array ? t.depth : 0u, t.colour_array, t.depth_array};
  glDeleteTextures(5, textures);
  t = ShadowTargets{};
}

MapTargets create_map_targets(int size, int layers, DepthFormat depth_format) {
  MapTargets t;
  t.size = size;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t.depth);
  glTextureStorage3D(t.depth, 1, depth_internal_format(depth_format), size, size, std::max(layers, 1));
  glTextureParameteri(t.depth, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.depth, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.depth, GL_TEXTURE_WRAP_S,
                      GL_CLAMP_TO_EDGE);  // outside the map: the shader says unshadowed
  glTextureParameteri(t.depth, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check_allocation("the 2D shadow maps");
  t.fbos.resize(static_cast<size_t>(layers));
  if (layers > 0) glCreateFramebuffers(layers, t.fbos.data());
  for (int l = 0; l < layers; ++l) {
    glNamedFramebufferTextureLayer(t.fbos[l], GL_DEPTH_ATTACHMENT, t.depth, 0, l);
    glNamedFramebufferDrawBuffer(t.fbos[l], GL_NONE);
    glNamedFramebufferReadBuffer(t.fbos[l], GL_NONE);
    check_complete(t.fbos[l], "2D shadow map");
  }
  return t;
}

void destroy(MapTargets& t) {
  if (!t.fbos.empty()) glDeleteFramebuffers(static_cast<GLsizei>(t.fbos.size()), t.fbos.data());
  glDeleteTextures(1, &t.depth);
  t = MapTargets{};
}

LightingTargets create_lighting_targets(int width, int height, bool check_outputs) {
  LightingTargets t;
  t.width = width;
  t.height = height;
  t.color = create_2d(GL_RGBA8, width, height);
  if (check_outputs) {
    t.shadow_factor = create_2d(GL_R32F, width, height);
    t.position = create_2d(GL_RGBA32F, width, height);
  }
  glCreateRenderbuffers(1, &t.depth);
  glNamedRenderbufferStorage(t.depth, GL_DEPTH_COMPONENT32F, width, height);
  check_allocation("the lighting targets");
  glCreateFramebuffers(1, &t.fbo);
  glNamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT0, t.color, 0);
  if (check_outputs) {
    glNamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT1, t.shadow_factor, 0);
    glNamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT2, t.position, 0);
  }
  glNamedFramebufferRenderbuffer(t.fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.depth);
  // The timed framebuffer has one draw buffer: a renderer's. (With three bound, NVIDIA's GL paid for all
  // three even when the shader wrote one.)
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glNamedFramebufferDrawBuffers(t.fbo, check_outputs ? 3 : 1, buffers);
  check_complete(t.fbo, check_outputs ? "lighting (check)" : "lighting");
  return t;
}

void destroy(LightingTargets& t) {
  glDeleteFramebuffers(1, &t.fbo);
  const GLuint textures[] = {t.color, t.shadow_factor, t.position};
  glDeleteTextures(3, textures);  // zero names are ignored
  glDeleteRenderbuffers(1, &t.depth);
  t = LightingTargets{};
}

}  // namespace omnishadow::gl
