#include "scene/scene_builder.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "scene/scene_error.h"

namespace lancer {

namespace {
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

bool SceneBuilder::add_triangle(const glm::vec3 p[3], std::uint32_t material, std::uint32_t source_id,
                                const CornerAttributes& attribs) {
  for (int k = 0; k < 3; ++k)
    if (!finite(p[k]))
      throw SceneError(file_, "triangle " + std::to_string(source_id) + " has a non-finite (NaN or Inf) position");

  // Zero area: the cross product vanishes (in double, so tiny but valid triangles stay).
  const glm::dvec3 e1 = glm::dvec3(p[1]) - glm::dvec3(p[0]);
  const glm::dvec3 e2 = glm::dvec3(p[2]) - glm::dvec3(p[0]);
  if (glm::cross(e1, e2) == glm::dvec3(0.0)) {
    ++scene_.stats.degenerate_dropped;
    return false;
  }

  scene_.triangles.push_back(p[0], p[1], p[2]);
  scene_.material_id.push_back(material);
  scene_.source_triangle_id.push_back(source_id);

  std::uint8_t flags = 0;
  for (int k = 0; k < 3; ++k) {
    glm::vec3 n(0.0f);
    if (attribs.normals) {
      n = attribs.normals[k];
      const float len = glm::length(n);
      if (!(len > 0.0f) || !std::isfinite(len)) {
        ++scene_.stats.zero_normals_repaired;
        n = glm::vec3(0.0f);  // flagged below: shading falls back to the geometric normal
      } else {
        n /= len;
      }
    }
    scene_.normals.push_back(n);
    scene_.texcoords.push_back(attribs.texcoords ? attribs.texcoords[k] : glm::vec2(0.0f));
    scene_.tangents.push_back(attribs.tangents ? attribs.tangents[k] : glm::vec4(0.0f));
  }
  if (attribs.normals) {
    const std::size_t base = scene_.normals.size() - 3;
    bool all_valid = true;
    for (int k = 0; k < 3; ++k) all_valid = all_valid && scene_.normals[base + k] != glm::vec3(0.0f);
    if (all_valid) flags |= kHasNormals;
  }
  if (attribs.texcoords) flags |= kHasTexcoords;
  if (attribs.tangents) flags |= kHasTangents;
  // texcoords1 stays empty until a triangle has TEXCOORD_1; the earlier corners then
  // get zeros so the array lines up with the others.
  if (attribs.texcoords1 || !scene_.texcoords1.empty()) {
    scene_.texcoords1.resize(scene_.texcoords.size() - 3);  // a no-op once it is in use
    for (int k = 0; k < 3; ++k)
      scene_.texcoords1.push_back(attribs.texcoords1 ? attribs.texcoords1[k] : glm::vec2(0.0f));
  }
  if (attribs.texcoords1) flags |= kHasTexcoords1;
  scene_.attrib_flags.push_back(flags);
  return true;
}

void SceneBuilder::finish() {
  if (scene_.materials.empty()) {
    Material m;
    m.name = "default";
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    scene_.materials.push_back(m);
  }
  for (std::uint32_t id : scene_.material_id)
    if (id >= scene_.materials.size())
      throw SceneError(file_, "material index " + std::to_string(id) + " out of range");
}

}  // namespace lancer
