#include "bench/run/scene_library.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "bench/truth/truth_cache.h"
#include "scenes/tessellate.h"

namespace omnishadow::bench {

namespace fs = std::filesystem;

// A name without '/' or a file extension is a bundled scene, anything else a file.
static std::string file_of_scene(const std::string& name, const std::string& scenes_dir) {
  if (name.find('/') != std::string::npos || name.ends_with(".json") || scene::is_model_file(name))
    return name;
  return (fs::path(scenes_dir) / (name + ".json")).string();
}

std::string SceneLibrary::path(const std::string& name) const {
  if (auto it = files_.find(name); it != files_.end()) return it->second;
  return file_of_scene(name, scenes_dir_);
}

std::string SceneLibrary::add(const std::string& name_or_path) {
  const std::string file = file_of_scene(name_or_path, scenes_dir_);
  std::string name = name_or_path;
  if (file != (fs::path(scenes_dir_) / (name_or_path + ".json")).string()) {
    name = fs::path(file).stem().string();
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
    if (name.empty()) throw std::invalid_argument("--scene: '" + name_or_path + "' names no file");
  }
  std::error_code ec;
  auto same_file = [&](const std::string& a, const std::string& b) {
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
  };
  // `--scene room,other/room.json` would give one id to two scenes. (A file named like a bundled scene that
  // this run does not use is fine: ids are per run.)
  if (auto it = files_.find(name); it != files_.end() && !same_file(it->second, file))
    throw std::invalid_argument("--scene: " + file + " and " + it->second + " would both be named '" + name +
                                "' in case ids; rename one of them");
  files_[name] = file;
  return name;
}

const scene::Scene& SceneLibrary::get(const std::string& name, bool rebase_origin, int tessellation) {
  const std::string key = scene_key(name, rebase_origin, tessellation);
  auto it = loaded_.find(key);
  if (it != loaded_.end()) return it->second;
  scene::LoadOptions load;
  load.rebase_origin = rebase_origin;
  load.light = light_;
  load.camera = camera_;
  scene::Scene s = scene::load_scene_file(path(name), load);
  s.name = name;
  scene::tessellate(s, tessellation);
  for (const std::string& note : s.notes) std::fprintf(stderr, "scene %s: %s\n", name.c_str(), note.c_str());
  return loaded_.emplace(key, std::move(s)).first->second;
}

}  // namespace omnishadow::bench
