#pragma once
// The triangles of a parsed glTF model (scenes/gltf_loader.h): the part that trusts nothing in the file.
// Every index is checked before it is used, every accessor against its buffer view and buffer, every count
// against the vertex limit before memory is reserved, and the node graph for cycles.

#include <tiny_gltf.h>

#include <cstdint>
#include <string>

#include "scenes/gltf_loader.h"

namespace omnishadow::scene {

// `name` prefixes every error (the file).
GltfModel gltf_model_from(const tinygltf::Model& model, const std::string& name, uint64_t max_vertices);

}  // namespace omnishadow::scene
