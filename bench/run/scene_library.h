#pragma once
// The scenes of a run: the names cases use for them (a bundled scene by its name, a file by its stem), and
// each scene loaded once per load option (--light / --camera applied, the rebase remedy, tessellation).

#include <map>
#include <optional>
#include <string>

#include "scenes/scene.h"

namespace omnishadow::bench {

class SceneLibrary {
 public:
  SceneLibrary(std::string scenes_dir, std::optional<scene::LightPlacement> light,
               std::optional<scene::CameraPlacement> camera)
      : scenes_dir_(std::move(scenes_dir)), light_(std::move(light)), camera_(std::move(camera)) {}
  // The name cases use for a scene given by name or path: a bundled name is itself; a file (a scene file or a
  // model) is named by its stem, with characters other than letters, digits, '.', '_' and '-' made '_', so
  // that ids read gl/bunny/c512/... Later calls with that name load the file. Throws std::invalid_argument
  // when two different files would share a name.
  std::string add(const std::string& name_or_path);
  // Loads (and caches) a scene by name or path; throws scene::SceneError.
  const scene::Scene& get(const std::string& name_or_path, bool rebase_origin, int tessellation);

 private:
  std::string path(const std::string& name_or_path) const;

  std::string scenes_dir_;  // where a bundled name finds <name>.json
  std::optional<scene::LightPlacement> light_;
  std::optional<scene::CameraPlacement> camera_;
  std::map<std::string, std::string> files_;    // add()'s names -> the files they stand for
  std::map<std::string, scene::Scene> loaded_;  // by scene_key
};

}  // namespace omnishadow::bench
