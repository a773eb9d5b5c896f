// Atlas re-plans (CaseConfig::atlas_replan_frames): the tiles sized again from a later frame's camera and
// lights, within the atlas as allocated. A re-plan keeps every block whose size did not change where it was:
// a block that moves must render again (its texels are elsewhere), and a fresh shelf packing moves every
// block after the first whose size changed.

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/common/atlas.h"

namespace omnishadow::atlas {

namespace {

struct Box {
  int x0, y0, x1, y1;  // half-open, in texels
  bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

Box box_of(const Block& b) {
  return {b.x, b.y, b.x + block_width(b.face_size), b.y + block_height(b.face_size)};
}

// Sizes face_sizes_within gave for width x height: by_distance no block is larger than the kept rectangle's
// own (pack_into's row as wide as the atlas holds them), by_coverage the scale was chosen so that they fit.
Plan packed_afresh(std::span<const int> sizes, int frame, int width, int height) {
  std::optional<Plan> plan = pack_into(sizes, width, height);
  if (!plan)
    throw std::logic_error("a re-plan of " + std::to_string(sizes.size()) + " lights at frame " +
                           std::to_string(frame) + " does not fit the " + std::to_string(width) + "x" +
                           std::to_string(height) + " atlas");
  return *plan;
}

std::vector<int> sizes_of(const Plan& plan) {
  std::vector<int> sizes;
  for (const Block& b : plan.lights) sizes.push_back(b.face_size);
  return sizes;
}

}  // namespace

int planned_frame(const CaseConfig& config, int frame) {
  const int every = config.atlas_replan_frames;
  if (every <= 0 || config.atlas_tiles == AtlasTiles::uniform || frame <= 0) return 0;
  return frame - frame % every;
}

Plan pack_frame(const CaseConfig& config, const scene::Scene& scene, int frame, int width, int height) {
  return packed_afresh(face_sizes_within(config, scene, frame, width, height), frame, width, height);
}

// Candidate corners: x at 0 or a placed block's right edge, y at 0 or a placed block's bottom edge (the
// bottom-left rule's corners, enough for a block to touch what it rests against), lowest row first.
std::optional<Plan> place_keeping(const Plan& before, std::span<const int> sizes) {
  if (sizes.size() != before.lights.size()) return std::nullopt;
  Plan plan{before.width, before.height, std::vector<Block>(sizes.size())};
  std::vector<Box> placed;
  std::vector<size_t> moving;
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (sizes[k] == before.lights[k].face_size) {
      plan.lights[k] = before.lights[k];
      placed.push_back(box_of(before.lights[k]));
    } else {
      moving.push_back(k);
    }
  }
  std::stable_sort(moving.begin(), moving.end(), [&](size_t a, size_t b) { return sizes[a] > sizes[b]; });
  for (size_t k : moving) {
    std::vector<int> xs{0}, ys{0};
    for (const Box& b : placed) xs.push_back(b.x1), ys.push_back(b.y1);
    std::sort(xs.begin(), xs.end());
    std::sort(ys.begin(), ys.end());
    const int w = block_width(sizes[k]), h = block_height(sizes[k]);
    bool found = false;
    for (size_t j = 0; j < ys.size() && !found; ++j)
      for (size_t i = 0; i < xs.size() && !found; ++i) {
        const Box at{xs[i], ys[j], xs[i] + w, ys[j] + h};
        if (at.x1 > before.width || at.y1 > before.height) continue;
        if (std::any_of(placed.begin(), placed.end(), [&](const Box& b) { return b.overlaps(at); })) continue;
        plan.lights[k] = {at.x0, at.y0, sizes[k]};
        placed.push_back(at);
        found = true;
      }
    if (!found) return std::nullopt;
  }
  return plan;
}

Plan replan(const CaseConfig& config, const scene::Scene& scene, int frame, const Plan& before) {
  const std::vector<int> sizes =
      face_sizes_within(config, scene, frame, before.width, before.height, sizes_of(before));
  if (std::optional<Plan> kept = place_keeping(before, sizes)) return *kept;
  return packed_afresh(sizes, frame, before.width, before.height);
}

// Each re-plan from the one before, from frame 0's: a plan depends on the frames planned before it, and this
// chain is the one every reader walks.
Plan plan_at(const CaseConfig& config, const scene::Scene& scene, int frame) {
  Plan plan = plan_for(config, scene);
  const int at = planned_frame(config, frame);
  for (int r = config.atlas_replan_frames; at > 0 && r <= at; r += config.atlas_replan_frames)
    plan = replan(config, scene, r, plan);
  return plan;
}

Plan plan_after(const CaseConfig& config, const scene::Scene& scene, int at, const Plan& current,
                int current_at) {
  if (at == current_at + config.atlas_replan_frames) return replan(config, scene, at, current);
  return plan_at(config, scene, at);
}

std::vector<uint8_t> moved_blocks(const Plan& was, const Plan& now) {
  std::vector<uint8_t> moved;
  for (size_t k = 0; k < was.lights.size() && k < now.lights.size(); ++k) {
    const Block &a = was.lights[k], &b = now.lights[k];
    moved.push_back(a.x != b.x || a.y != b.y || a.face_size != b.face_size);
  }
  return moved;
}

}  // namespace omnishadow::atlas
