#include "backends/vulkan/vk_targets.h"

#include "backends/common/layouts.h"
#include "backends/common/techniques.h"

namespace omnishadow::vk {
namespace {

VkAttachmentDescription attachment(VkFormat format, VkAttachmentStoreOp store, VkImageLayout final_layout,
                                   bool loads = false) {
  VkAttachmentDescription a{};
  a.format = format;
  a.samples = VK_SAMPLE_COUNT_1_BIT;
  a.loadOp = loads ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;  // else: from the clear values
  a.storeOp = loads ? VK_ATTACHMENT_STORE_OP_STORE : store;  // an atlas keeps the tiles of lights not redrawn
  a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  a.initialLayout = loads ? final_layout : VK_IMAGE_LAYOUT_UNDEFINED;
  a.finalLayout = final_layout;
  return a;
}

// One subpass: `colors` colour attachments first, then the depth attachment. The external dependencies order
// the pass after earlier reads of its images (sampling, copies) and make its writes visible to `consumer`.
VkRenderPass create_render_pass(VkContext& ctx, const std::vector<VkAttachmentDescription>& attachments,
                                uint32_t colors, VkPipelineStageFlags consumer_stage,
                                VkAccessFlags consumer_access, uint32_t view_mask) {
  std::vector<VkAttachmentReference> color_refs;
  for (uint32_t i = 0; i < colors; ++i) color_refs.push_back({i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
  VkAttachmentReference depth_ref{colors, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = colors;
  subpass.pColorAttachments = color_refs.data();
  subpass.pDepthStencilAttachment = &depth_ref;
  const VkPipelineStageFlags attachment_stages = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  const VkAccessFlags attachment_writes =
      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  VkSubpassDependency deps[2] = {};
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[0].srcStageMask = consumer_stage | attachment_stages;
  deps[0].dstStageMask = attachment_stages;
  deps[0].srcAccessMask = attachment_writes;
  deps[0].dstAccessMask = attachment_writes | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
  deps[1].srcSubpass = 0;
  deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  deps[1].srcStageMask = attachment_stages;
  deps[1].dstStageMask = consumer_stage;
  deps[1].srcAccessMask = attachment_writes;
  deps[1].dstAccessMask = consumer_access;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = static_cast<uint32_t>(attachments.size());
  info.pAttachments = attachments.data();
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 2;
  info.pDependencies = deps;
  VkRenderPassMultiviewCreateInfo multiview{VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO};
  multiview.subpassCount = 1;
  multiview.pViewMasks = &view_mask;
  if (view_mask) info.pNext = &multiview;
  VkRenderPass pass = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateRenderPass(ctx.device(), &info, nullptr, &pass));
  return pass;
}

VkFramebuffer create_framebuffer(VkContext& ctx, VkRenderPass pass, const std::vector<VkImageView>& views,
                                 uint32_t width, uint32_t height, uint32_t layers) {
  VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  info.renderPass = pass;
  info.attachmentCount = static_cast<uint32_t>(views.size());
  info.pAttachments = views.data();
  info.width = width;
  info.height = height;
  info.layers = layers;
  VkFramebuffer fb = VK_NULL_HANDLE;
  OMNISHADOW_VK(vkCreateFramebuffer(ctx.device(), &info, nullptr, &fb));
  return fb;
}

}  // namespace

VkFormat depth_format_of(DepthFormat format) {
  switch (format) {
    case DepthFormat::d16:
      return VK_FORMAT_D16_UNORM;
    case DepthFormat::d24:
      return VK_FORMAT_X8_D24_UNORM_PACK32;
    case DepthFormat::d32f:
      return VK_FORMAT_D32_SFLOAT;
  }
  return VK_FORMAT_D32_SFLOAT;
}

VkFormat colour_format_of(ColourFormat format) {
  switch (format) {
    case ColourFormat::r32f:
      return VK_FORMAT_R32_SFLOAT;
    case ColourFormat::rg32f:
      return VK_FORMAT_R32G32_SFLOAT;
    case ColourFormat::rg16f:
      return VK_FORMAT_R16G16_SFLOAT;
    case ColourFormat::r16f:
      return VK_FORMAT_R16_SFLOAT;
    case ColourFormat::rgba32f:
      return VK_FORMAT_R32G32B32A32_SFLOAT;
    case ColourFormat::rgba16f:
      return VK_FORMAT_R16G16B16A16_SFLOAT;
    case ColourFormat::none:
      break;
  }
  return VK_FORMAT_UNDEFINED;
}

// six_pass: each light's faces a framebuffer of single-layer views each. Layered: one framebuffer per light
// of its layers' array views (gl_Layer picks the face). Multiview: the same views with layers = 1; the view
// mask routes.
static void create_shadow_framebuffers(VkContext& ctx, ShadowTargets& t, bool has_colour,
                                       const TechniqueTraits& technique, bool all_lights) {
  auto views_for = [&](uint32_t first, uint32_t count) {
    std::vector<VkImageView> views;
    VkImageViewType type = count == 1 ? VK_IMAGE_VIEW_TYPE_2D : VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    if (has_colour) views.push_back(create_view(ctx, t.color, type, first, count));
    views.push_back(create_view(ctx, t.depth, type, first, count));
    t.attachment_views.insert(t.attachment_views.end(), views.begin(), views.end());
    return views;
  };
  const uint32_t layers = t.layers;
  for (uint32_t k = 0; k < t.lights; ++k) {
    if (technique.passes == 6) {  // one pass per face, or per layer
      for (uint32_t f = 0; f < layers; ++f)
        t.framebuffers.push_back(
            create_framebuffer(ctx, t.render_pass, views_for(k * layers + f, 1), t.size, t.size, 1));
    } else {
      t.framebuffers.push_back(create_framebuffer(ctx, t.render_pass, views_for(k * layers, layers), t.size,
                                                  t.size, technique.multiview ? 1 : layers));
    }
  }
  if (all_lights)
    t.all_lights_framebuffer = create_framebuffer(ctx, t.render_pass, views_for(0, layers * t.lights), t.size,
                                                  t.size, layers * t.lights);
}

// Layout atlas: one framebuffer over the whole layer. Its render pass loads, so the images start in the
// layouts the pass expects (their contents are each light's clears).
static void create_atlas_framebuffer(VkContext& ctx, ShadowTargets& t, bool has_colour,
                                     VkImageLayout colour_layout, VkImageLayout depth_layout) {
  ctx.submit_and_wait([&](VkCommandBuffer cb) {
    if (has_colour)
      transition(cb, t.color, VK_IMAGE_LAYOUT_UNDEFINED, colour_layout, 0, 0,
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    transition(cb, t.depth, VK_IMAGE_LAYOUT_UNDEFINED, depth_layout, 0, 0, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
               VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  });
  if (has_colour) t.attachment_views.push_back(create_view(ctx, t.color, VK_IMAGE_VIEW_TYPE_2D, 0, 1));
  t.attachment_views.push_back(create_view(ctx, t.depth, VK_IMAGE_VIEW_TYPE_2D, 0, 1));
  t.framebuffers.push_back(
      create_framebuffer(ctx, t.render_pass, t.attachment_views, t.depth.width, t.depth.height, 1));
}

ShadowTargets create_shadow_targets(VkContext& ctx, const CaseConfig& c, const scene::Scene& scene) {
  ShadowTargets t;
  t.storage = c.storage;
  t.size = static_cast<uint32_t>(layer_size(c.layout, c.cube_size));
  if (c.layout == Layout::atlas) t.atlas = atlas::plan_for(c, scene);
  // Six cube-compatible layers, or a layout's own (dual_paraboloid: two of a plain 2D array); an atlas: one.
  const uint32_t layers = static_cast<uint32_t>(traits(c.layout).geometry.layers);
  const bool cube = layers == 6 && !t.atlas;
  const uint32_t width = t.atlas ? uint32_t(t.atlas->width) : t.size,
                 height = t.atlas ? uint32_t(t.atlas->height) : t.size;
  t.layers = layers;
  t.lights = static_cast<uint32_t>(c.light_count);
  const uint32_t all_layers = t.atlas ? 1u : layers * t.lights;
  const VkFormat colour = colour_format_of(colour_format(c.storage, c.depth_format));
  const bool has_colour = colour != VK_FORMAT_UNDEFINED, colour_checked = traits(c.storage).colour_checked;
  const bool moments = traits(c.storage).moments != MomentKind::none;
  const VkFormat depth_format = depth_format_of(c.depth_format);
  try {
    t.depth =
        create_image(ctx, depth_format, width, height, all_layers, cube,
                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                         (colour_checked ? 0 : VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT));
    const VkImageUsageFlags storage_usage = moments ? VK_IMAGE_USAGE_STORAGE_BIT : 0;
    if (has_colour)
      t.color = create_image(ctx, colour, width, height, all_layers, cube,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT | storage_usage);
    if (moments)
      t.blur = create_image(ctx, colour, width, height, all_layers, false, VK_IMAGE_USAGE_STORAGE_BIT);
    // Layouts other than the cube sample their layers as a 2D array (the shader picks the layer).
    const LayoutLookup lookup = traits(c.layout).lookup;
    const bool cube_per_light = light_cubes(c);
    t.sampled_view =
        create_view(ctx, moments ? t.color : t.stored(),
                    lookup == LayoutLookup::hardware_cube && !cube_per_light ? VK_IMAGE_VIEW_TYPE_CUBE
                    : lookup == LayoutLookup::hardware_cube_array            ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY
                                                                             : VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                    0, all_layers);
    for (uint32_t k = 0; cube_per_light && k < t.lights; ++k)
      t.light_cube_views.push_back(
          create_view(ctx, moments ? t.color : t.stored(), VK_IMAGE_VIEW_TYPE_CUBE, k * layers, layers));

    // The moments stay in GENERAL: the blur reads and writes them as storage images, the lighting pass
    // samples them.
    std::vector<VkAttachmentDescription> attachments;
    const bool loads = t.atlas.has_value();
    const VkImageLayout colour_layout =
        moments ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const VkImageLayout depth_layout = colour_checked ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                                                      : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    if (has_colour)
      attachments.push_back(attachment(colour, VK_ATTACHMENT_STORE_OP_STORE, colour_layout, loads));
    attachments.push_back(attachment(
        depth_format, colour_checked ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
        depth_layout, loads));
    const TechniqueTraits& technique = traits(c.technique);
    const uint32_t view_mask = technique.multiview ? 0b111111u : 0u;
    t.render_pass = create_render_pass(
        ctx, attachments, has_colour ? 1 : 0,
        VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
            (moments ? VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT : 0),
        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | (moments ? VK_ACCESS_SHADER_WRITE_BIT : 0),
        view_mask);

    if (t.atlas)
      create_atlas_framebuffer(ctx, t, has_colour, colour_layout, depth_layout);
    else
      create_shadow_framebuffers(ctx, t, has_colour, technique,
                                 c.light_grouping == LightGrouping::all_lights);
  } catch (...) {
    destroy(ctx, t);
    throw;
  }
  return t;
}

void destroy(VkContext& ctx, ShadowTargets& t) {
  for (VkFramebuffer fb : t.framebuffers) vkDestroyFramebuffer(ctx.device(), fb, nullptr);
  if (t.all_lights_framebuffer) vkDestroyFramebuffer(ctx.device(), t.all_lights_framebuffer, nullptr);
  for (VkImageView v : t.attachment_views) vkDestroyImageView(ctx.device(), v, nullptr);
  for (VkImageView v : t.light_cube_views) vkDestroyImageView(ctx.device(), v, nullptr);
  if (t.sampled_view) vkDestroyImageView(ctx.device(), t.sampled_view, nullptr);
  if (t.render_pass) vkDestroyRenderPass(ctx.device(), t.render_pass, nullptr);
  destroy(ctx, t.blur);
  destroy(ctx, t.color);
  destroy(ctx, t.depth);
  t = ShadowTargets{};
}

MapTargets create_map_targets(VkContext& ctx, uint32_t size, uint32_t layers, DepthFormat format) {
  MapTargets t;
  t.size = size;
  t.layers = layers;
  const VkFormat depth_format = depth_format_of(format);
  try {
    t.depth = create_image(ctx, depth_format, size, size, layers, false,
                           VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                               VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    t.sampled_view = create_view(ctx, t.depth, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, layers);
    t.render_pass = create_render_pass(
        ctx,
        {attachment(depth_format, VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)}, 0,
        VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT, 0);
    for (uint32_t l = 0; l < layers; ++l) {
      t.layer_views.push_back(create_view(ctx, t.depth, VK_IMAGE_VIEW_TYPE_2D, l, 1));
      t.framebuffers.push_back(create_framebuffer(ctx, t.render_pass, {t.layer_views.back()}, size, size, 1));
    }
  } catch (...) {
    destroy(ctx, t);
    throw;
  }
  return t;
}

void destroy(VkContext& ctx, MapTargets& t) {
  for (VkFramebuffer fb : t.framebuffers) vkDestroyFramebuffer(ctx.device(), fb, nullptr);
  for (VkImageView v : t.layer_views) vkDestroyImageView(ctx.device(), v, nullptr);
  if (t.sampled_view) vkDestroyImageView(ctx.device(), t.sampled_view, nullptr);
  if (t.render_pass) vkDestroyRenderPass(ctx.device(), t.render_pass, nullptr);
  destroy(ctx, t.depth);
  t = MapTargets{};
}

LightingTargets create_lighting_targets(VkContext& ctx, uint32_t width, uint32_t height, bool check_outputs) {
  LightingTargets t;
  t.width = width;
  t.height = height;
  try {
    const VkImageUsageFlags color_usage =
        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    t.color = create_image(ctx, VK_FORMAT_R8G8B8A8_UNORM, width, height, 1, false, color_usage);
    std::vector<const Image*> colors = {&t.color};
    if (check_outputs) {
      t.shadow_factor = create_image(ctx, VK_FORMAT_R32_SFLOAT, width, height, 1, false, color_usage);
      t.position = create_image(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, width, height, 1, false, color_usage);
      colors.push_back(&t.shadow_factor);
      colors.push_back(&t.position);
    }
    t.depth = create_image(ctx, VK_FORMAT_D32_SFLOAT, width, height, 1, false,
                           VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
    std::vector<VkAttachmentDescription> attachments;
    for (const Image* i : colors)
      attachments.push_back(
          attachment(i->format, VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL));
    attachments.push_back(attachment(VK_FORMAT_D32_SFLOAT, VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL));
    t.render_pass = create_render_pass(ctx, attachments, static_cast<uint32_t>(colors.size()),
                                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, 0);
    for (const Image* i : colors) t.views.push_back(create_view(ctx, *i, VK_IMAGE_VIEW_TYPE_2D, 0, 1));
    t.views.push_back(create_view(ctx, t.depth, VK_IMAGE_VIEW_TYPE_2D, 0, 1));
    t.framebuffer = create_framebuffer(ctx, t.render_pass, t.views, width, height, 1);
  } catch (...) {
    destroy(ctx, t);
    throw;
  }
  return t;
}

void destroy(VkContext& ctx, LightingTargets& t) {
  if (t.framebuffer) vkDestroyFramebuffer(ctx.device(), t.framebuffer, nullptr);
  for (VkImageView v : t.views) vkDestroyImageView(ctx.device(), v, nullptr);
  if (t.render_pass) vkDestroyRenderPass(ctx.device(), t.render_pass, nullptr);
  for (Image* i : {&t.color, &t.shadow_factor, &t.position, &t.depth}) destroy(ctx, *i);
  t = LightingTargets{};
}

}  // namespace omnishadow::vk
