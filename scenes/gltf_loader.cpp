#include "scenes/gltf_loader.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "scenes/gltf_geometry.h"
#include "scenes/model_util.h"

namespace omnishadow::scene {
namespace {

namespace fs = std::filesystem;

// Where tinygltf may read a .gltf's buffers and images from: the model's own folder and below, nothing else.
struct Sandbox {
  std::string root;     // canonical folder of the model; empty: no file may be read (bytes given)
  std::string refused;  // the first path refused for leaving it, for the error
  std::string missing;  // the first path inside it that does not exist: a missing buffer or image
};

bool inside_sandbox(const std::string& path, Sandbox& box) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  const std::string text = canonical.string();
  const bool inside = !ec && !box.root.empty() && text.rfind(box.root + "/", 0) == 0;
  if (!inside && box.refused.empty()) box.refused = path;
  return inside;
}

bool sandbox_exists(const std::string& path, void* user) {
  std::error_code ec;
  Sandbox& box = *static_cast<Sandbox*>(user);
  if (!inside_sandbox(path, box)) return false;
  if (fs::is_regular_file(path, ec)) return true;
  if (box.missing.empty()) box.missing = path;
  return false;
}

std::string sandbox_expand(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool sandbox_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  std::error_code ec;
  if (!sandbox_exists(path, user)) {
    if (err) *err += "cannot read " + path + "\n";
    return false;
  }
  const uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > (uintmax_t(1) << 31)) {
    if (err) *err += path + ": larger than 2 GiB\n";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(size_t(bytes));
  return bool(in.read(reinterpret_cast<char*>(out->data()), std::streamsize(bytes)));
}

bool sandbox_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not allowed\n";
  return false;
}

// Images are not decoded: shadows need geometry only.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
  return true;
}

GltfModel load(const std::string& bytes, const std::string& name, const std::string& folder,
               uint64_t max_vertices) {
  if (bytes.size() > 0xffffffffu) throw std::runtime_error(name + ": larger than 4 GiB");
  Sandbox box;
  if (!folder.empty()) {
    std::error_code ec;
    box.root = fs::weakly_canonical(folder, ec).string();
    if (ec) box.root.clear();
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({sandbox_exists, sandbox_expand, sandbox_read, sandbox_write, &box});
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const std::string extension = fs::path(name).extension().string();
  if (!binary && (extension == ".glb" || extension == ".GLB"))
    throw std::runtime_error(name + ": not a binary glTF (a .glb starts with 'glTF')");
  const std::string base_dir = box.root.empty() ? std::string("/nonexistent-omnishadow-sandbox") : box.root;
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(bytes.data()),
                                                       static_cast<unsigned>(bytes.size()), base_dir)
                         : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                      static_cast<unsigned>(bytes.size()), base_dir);
  // A file the model names that is not in its folder is missing; a URI that climbs out of it is refused. Only
  // a buffer can fail the load: images are never decoded (tinygltf reads an external image as optional), so a
  // texture that is missing or lies elsewhere blocks nothing.
  if (!ok && !box.missing.empty())
    throw std::runtime_error(name + ": " + fs::path(box.missing).filename().string() +
                             " is missing (a buffer the model names; looked for in " + box.root + ")");
  if (!ok && !box.refused.empty())
    throw std::runtime_error(name + ": a buffer URI leaves the model's folder (" + box.refused + ")");
  if (!ok) throw std::runtime_error(name + ": " + first_line(err, "not a glTF 2.0 file"));
  return gltf_model_from(model, name, max_vertices);
}

}  // namespace

GltfModel load_gltf(const std::string& path, uint64_t max_vertices) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw std::runtime_error("cannot open glTF file " + path);
  const uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > (uintmax_t(1) << 31))
    throw std::runtime_error(path + ": larger than 2 GiB or unreadable");
  std::ifstream in(path, std::ios::binary);
  std::string text(size_t(bytes), '\0');
  if (!in.read(text.data(), std::streamsize(bytes)))
    throw std::runtime_error("cannot read glTF file " + path);
  return load(text, path,
              fs::path(path).parent_path().string().empty() ? "." : fs::path(path).parent_path().string(),
              max_vertices);
}

GltfModel load_gltf_bytes(const std::string& bytes, const std::string& name, uint64_t max_vertices) {
  return load(bytes, name, "", max_vertices);
}

}  // namespace omnishadow::scene
