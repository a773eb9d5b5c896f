// The update budget's check: what each face of each light holds, frame by frame, held to the lights' paths
// (functions of the frame index), independently of the planner's own bookkeeping of what is stale.

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "backends/common/case_support.h"
#include "backends/common/cube_faces.h"
#include "backends/common/shadow_plan.h"
#include "bench/truth/case_checks.h"

namespace omnishadow::bench {

bool moves_within(const scene::LightPath& path, int last_frame) {
  for (int t = 1; t <= last_frame; ++t)
    if (path.at(t) != path.at(0)) return true;
  return false;
}

namespace {

// Whether face `face` of point light `light`, rendered at frame `content`, still holds what frame `now` has:
// its light where it was, and no moving caster that reached the face moved in between.
bool holds(const scene::Scene& scene, int light, int face, int content, int now) {
  const scene::PointLight& l = scene.point_lights.at(size_t(light));
  const glm::vec3 held = l.path.at(content);
  return l.path.at(now) == held &&
         !((cube::moved_caster_faces(scene, held, l.near_plane, l.far_plane, content, now) >> face) & 1u);
}

// Frames a face has waited at sequence index `i`: those up to and including it that read the face (in view)
// while it held an older frame's light or casters. 0 for a face that is up to date.
int wait_of(const std::vector<SequenceFrame>& frames, size_t i, int light, int face,
            const scene::Scene& scene) {
  const int content = frames[i].face_frames[size_t(light)][size_t(face)];
  int wait = 0;
  for (size_t j = 0; j <= i; ++j) {
    const SequenceFrame& s = frames[j];
    if (s.frame <= content || holds(scene, light, face, content, s.frame)) continue;
    wait += (s.read_faces[size_t(light)] >> face) & 1u;
  }
  return wait;
}

// The faces of point light `light` that can go stale within frames 0..last_frame: every face where its light
// moves (or where its range is fitted to bounds that moving casters change), else those a moving caster
// reaches at some frame of them.
uint8_t faces_that_can_go_stale(const CaseConfig& c, const scene::Scene& scene, int light, int last_frame) {
  const scene::PointLight& l = scene.point_lights.at(size_t(light));
  if (moves_within(l.path, last_frame)) return cube::kAllFaces;
  if (c.optimizations.fit_range && scene.has_moving_objects()) return cube::kAllFaces;
  uint8_t faces = 0;
  for (int t = 1; t <= last_frame; ++t)
    faces |= cube::moved_caster_faces(scene, l.path.at(0), l.near_plane, l.far_plane, 0, t);
  return faces;
}

// ceil(units that can be stale / units refreshed a frame) - 1: the oldest-first order serves every unit that
// went stale before a given one ahead of it, each once, so that one waits at most that many frames read.
int wait_bound(const CaseConfig& c, const scene::Scene& scene, int last_frame) {
  if (c.update_budget_faces <= 0) return 0;
  const bool single = refreshes_single_faces(c);
  int units = 0;
  for (int k = 0; k < c.light_count && k < int(scene.point_lights.size()); ++k) {
    const uint8_t faces = faces_that_can_go_stale(c, scene, k, last_frame);
    units += single ? std::popcount(faces) : int(faces != 0);
  }
  const int per_frame = single ? c.update_budget_faces : c.update_budget_faces / cube::kFaceCount;
  return std::max(0, (units + per_frame - 1) / std::max(per_frame, 1) - 1);
}

// The faces sequence frame `i` rendered outside the budget: those it reads that held nothing the frame before
// (a face culled to the view until now) and now hold this frame's, where faces refresh alone; else every face
// rendered of a light with such a face (it renders whole); and every face rendered of a light an atlas
// re-plan moved (its texels are elsewhere: a first render of its new tiles).
int first_renders(const CaseConfig& c, const std::vector<SequenceFrame>& frames, size_t i) {
  if (i == 0) return 0;
  const SequenceFrame &s = frames[i], &before = frames[i - 1];
  const bool single = refreshes_single_faces(c);
  int faces = 0;
  for (size_t k = 0; k < s.face_frames.size() && k < before.face_frames.size(); ++k) {
    int first = 0, rendered = 0;
    for (int face = 0; face < cube::kFaceCount; ++face) {
      const bool now = s.face_frames[k][size_t(face)] == s.frame;
      rendered += now;
      first += now && before.face_frames[k][size_t(face)] < 0 && ((s.read_faces[k] >> face) & 1u);
    }
    const bool relocated = k < s.relocated.size() && s.relocated[k];
    faces += relocated ? rendered : single ? first : (first > 0 ? rendered : 0);
  }
  return faces;
}

// A light an atlas re-plan moved holds nothing from before that frame: its block is elsewhere now, so each of
// its faces holds that frame's depth or nothing (a face culled to the view). Empty when every one does.
std::string left_behind(const std::vector<SequenceFrame>& frames) {
  for (const SequenceFrame& s : frames)
    for (size_t k = 0; k < s.relocated.size() && k < s.face_frames.size(); ++k) {
      if (!s.relocated[k]) continue;
      for (int face = 0; face < cube::kFaceCount; ++face) {
        const int content = s.face_frames[k][size_t(face)];
        if (content < 0 || content == s.frame) continue;
        return "frame " + std::to_string(s.frame) + ": an atlas re-plan moved light " + std::to_string(k) +
               "'s block, but its face " + cube::kFaceNames[size_t(face)] + " holds frame " +
               std::to_string(content) + "'s (rendered where its block was, not rendered again)";
      }
    }
  return {};
}

}  // namespace

void check_update_budget(CaseFindings& r, const scene::Scene& scene, const std::vector<int>& lights,
                         const std::vector<SequenceFrame>& frames) {
  StalenessReport report;
  report.lights = lights;
  if (frames.empty()) return;
  report.wait_bound = wait_bound(r.config, scene, frames.back().frame);
  std::string unread, over_wait, over_budget;
  double rendered_sum = 0.0, error_sum = 0.0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const SequenceFrame& s = frames[i];
    StalenessFrame out{s.frame,
                       0,
                       0,
                       0,
                       s.misclassified_percent,
                       s.pixels,
                       int(std::count(s.relocated.begin(), s.relocated.end(), uint8_t{1}))};
    for (size_t k = 0; k < s.face_frames.size(); ++k) {
      for (int face = 0; face < cube::kFaceCount; ++face) {
        const int content = s.face_frames[k][size_t(face)];
        out.faces_rendered += content == s.frame;
        if (!((s.read_faces[k] >> face) & 1u)) continue;
        if (content < 0) {
          if (unread.empty())
            unread = "frame " + std::to_string(s.frame) + ": light " + std::to_string(k) + " face " +
                     cube::kFaceNames[size_t(face)] + " is read but holds no light's depth";
          continue;
        }
        const int wait = wait_of(frames, i, int(k), face, scene);
        out.faces_stale += wait > 0;
        out.max_wait = std::max(out.max_wait, wait);
        if (wait > report.wait_bound && over_wait.empty())
          over_wait = "frame " + std::to_string(s.frame) + ": light " + std::to_string(k) + " face " +
                      cube::kFaceNames[size_t(face)] + " has shown its light and casters of frame " +
                      std::to_string(content) + " for " + std::to_string(wait) + " frames, above the " +
                      std::to_string(report.wait_bound) + " that refreshing the oldest first allows";
      }
    }
    // The first frame renders every light whole, outside the budget (its maps must hold defined values), and
    // so does a later one each face it reads that held nothing (first_renders).
    const int first = first_renders(r.config, frames, i);
    if (i > 0 && r.config.update_budget_faces > 0 &&
        out.faces_rendered - first > r.config.update_budget_faces && over_budget.empty())
      over_budget = "frame " + std::to_string(s.frame) + " rendered " + std::to_string(out.faces_rendered) +
                    " faces (" + std::to_string(first) + " of them first renders of faces that held nothing" +
                    (out.lights_relocated ? " or of lights an atlas re-plan moved" : "") +
                    "), above the update budget of " + std::to_string(r.config.update_budget_faces);
    report.max_wait = std::max(report.max_wait, out.max_wait);
    if (i > 0) rendered_sum += out.faces_rendered;  // the steady state: the first frame renders everything
    error_sum += out.misclassified_percent;
    if (out.misclassified_percent > report.worst_misclassified_percent || i == 0) {
      report.worst_misclassified_percent = out.misclassified_percent;
      report.worst_frame = out.frame;
    }
    report.frames.push_back(out);
  }
  report.mean_faces_rendered = frames.size() > 1 ? rendered_sum / double(frames.size() - 1) : 0.0;
  report.mean_misclassified_percent = error_sum / double(frames.size());
  const std::map<std::string, double> figures = {{"max_wait", double(report.max_wait)},
                                                 {"wait_bound", double(report.wait_bound)}};
  std::string moved = left_behind(frames);
  for (const std::string* message : {&unread, &over_wait, &over_budget, &moved})
    if (!message->empty()) r.add({Status::failed_check, "update_budget", *message, figures});
  r.staleness = std::move(report);
}

}  // namespace omnishadow::bench
