#include "backends/common/meshlets.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace omnishadow::gpu {
namespace {

// A sphere around the meshlet's vertices: the centre of their box, the radius the largest distance to it in
// double and then rounded up, so the task stage's culling never drops a triangle that reaches a face.
glm::vec4 enclosing_sphere(const scene::Scene& scene, const uint32_t* vertices, uint32_t count) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t i = 0; i < count; ++i) {
    const glm::dvec3 p(scene.vertices[vertices[i]].position);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 centre(glm::vec3((lo + hi) * 0.5));
  double radius = 0.0;
  for (uint32_t i = 0; i < count; ++i)
    radius =
        std::max(radius, glm::length(glm::dvec3(scene.vertices[vertices[i]].position) - glm::dvec3(centre)));
  return {centre, std::nextafter(static_cast<float>(radius), INFINITY)};
}

}  // namespace

size_t MeshletData::bytes() const {
  return meshlets.size() * sizeof(Meshlet) + spheres.size() * sizeof(glm::vec4) +
         (vertices.size() + triangles.size()) * sizeof(uint32_t);
}

MeshletData build_meshlets(const scene::Scene& scene) {
  MeshletData out;
  for (const scene::Object& obj : scene.objects) {
    if (uint64_t(obj.first_vertex) + obj.vertex_count > scene.vertices.size())
      throw std::logic_error("build_meshlets: object '" + obj.name + "' reaches past the scene's " +
                             std::to_string(scene.vertices.size()) +
                             " vertices (a backend's copy, whose vertices live on the device?)");
    // Weld by position: remap[i] is the unique vertex of the object's i-th vertex.
    std::vector<glm::vec3> positions(obj.vertex_count);
    for (uint32_t i = 0; i < obj.vertex_count; ++i)
      positions[i] = scene.vertices[obj.first_vertex + i].position;
    std::vector<unsigned int> remap(obj.vertex_count);
    const size_t unique = meshopt_generateVertexRemap(remap.data(), nullptr, obj.vertex_count,
                                                      positions.data(), obj.vertex_count, sizeof(glm::vec3));
    std::vector<glm::vec3> unique_positions(unique);
    std::vector<uint32_t> unique_to_scene(unique);
    for (uint32_t i = 0; i < obj.vertex_count; ++i) {
      unique_positions[remap[i]] = positions[i];
      unique_to_scene[remap[i]] =
          obj.first_vertex + i;  // any of the welded copies: their positions are equal
    }
    const std::vector<unsigned int>& indices =
        remap;  // the unindexed triangle list, as indices of unique vertices

    const size_t bound =
        meshopt_buildMeshletsBound(indices.size(), kMaxMeshletVertices, kMaxMeshletTriangles);
    std::vector<meshopt_Meshlet> meshlets(bound);
    std::vector<unsigned int> meshlet_vertices(bound * kMaxMeshletVertices);
    std::vector<unsigned char> meshlet_triangles(bound * kMaxMeshletTriangles * 3);
    const size_t count =
        indices.empty()
            ? 0
            : meshopt_buildMeshlets(meshlets.data(), meshlet_vertices.data(), meshlet_triangles.data(),
                                    indices.data(), indices.size(), &unique_positions[0].x, unique,
                                    sizeof(glm::vec3), kMaxMeshletVertices, kMaxMeshletTriangles, 0.0f);
    const uint32_t first_meshlet = static_cast<uint32_t>(out.meshlets.size());
    for (size_t m = 0; m < count; ++m) {
      const meshopt_Meshlet& src = meshlets[m];
      Meshlet dst{static_cast<uint32_t>(out.vertices.size()), static_cast<uint32_t>(out.triangles.size()),
                  src.vertex_count, src.triangle_count};
      for (uint32_t v = 0; v < src.vertex_count; ++v)
        out.vertices.push_back(unique_to_scene[meshlet_vertices[src.vertex_offset + v]]);
      for (uint32_t t = 0; t < src.triangle_count; ++t) {
        const unsigned char* tri = &meshlet_triangles[src.triangle_offset + 3 * t];
        out.triangles.push_back(uint32_t(tri[0]) | uint32_t(tri[1]) << 8 | uint32_t(tri[2]) << 16);
      }
      out.spheres.push_back(enclosing_sphere(scene, &out.vertices[dst.vertex_offset], dst.vertex_count));
      out.meshlets.push_back(dst);
    }
    while (out.meshlets.size() % kMeshletsPerTask !=
           0) {  // padding: empty meshlets up to the next task group
      out.meshlets.push_back({0, 0, 0, 0});
      out.spheres.emplace_back(0.0f);
    }
    out.objects.push_back({first_meshlet / kMeshletsPerTask,
                           static_cast<uint32_t>(out.meshlets.size() - first_meshlet) / kMeshletsPerTask});
  }
  return out;
}

std::string mesh_launch_refusal(const MeshletData& data, uint32_t lights, bool emulated,
                                uint64_t launch_limit, const std::string& launch_name,
                                uint64_t dispatch_limit, const std::string& dispatch_name) {
  const std::string per = lights > 1 ? " (meshlet groups x " + std::to_string(lights) + " lights)" : "";
  if (emulated) {
    const uint64_t all = uint64_t(data.meshlets.size() / kMeshletsPerTask) * lights;
    if (all > dispatch_limit)
      return "mesh_shader's emulation dispatches the scene's " + std::to_string(all) + " task workgroups" +
             per + " at once, above " + dispatch_name + " " + std::to_string(dispatch_limit);
    return {};
  }
  uint64_t most = 0;
  for (const ObjectMeshlets& o : data.objects) most = std::max(most, uint64_t(o.task_count) * lights);
  if (most > launch_limit)
    return "mesh_shader launches an object's " + std::to_string(most) + " task workgroups" + per +
           " at once, above " + launch_name + " " + std::to_string(launch_limit);
  return {};
}

std::vector<MeshletRange> update_moving_spheres(const scene::Scene& posed, MeshletData& data) {
  std::vector<MeshletRange> out;
  for (size_t o = 0; o < posed.objects.size() && o < data.objects.size(); ++o) {
    if (!posed.objects[o].moves()) continue;
    const MeshletRange range{data.objects[o].first_task * kMeshletsPerTask,
                             data.objects[o].task_count * kMeshletsPerTask};
    for (uint32_t m = range.first; m < range.first + range.count; ++m) {
      const Meshlet& meshlet = data.meshlets[m];
      if (meshlet.triangle_count > 0)
        data.spheres[m] =
            enclosing_sphere(posed, &data.vertices[meshlet.vertex_offset], meshlet.vertex_count);
    }
    if (range.count > 0) out.push_back(range);
  }
  return out;
}

}  // namespace omnishadow::gpu
