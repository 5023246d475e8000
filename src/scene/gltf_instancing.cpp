#include "scene/gltf_instancing.h"

#include <tiny_gltf.h>

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

bool finite(const glm::dvec4& v) { return std::isfinite(v.x + v.y + v.z + v.w); }

}  // namespace

std::optional<std::vector<glm::dmat4>> instance_transforms(const ModelRef& m, int node, std::size_t mesh_triangles) {
  const tinygltf::Node& n = m.model.nodes[std::size_t(node)];
  const auto ext = n.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == n.extensions.end()) return std::nullopt;
  const std::string what = "node " + std::to_string(node) + " EXT_mesh_gpu_instancing";
  if (!ext->second.IsObject() || !ext->second.Has("attributes") || !ext->second.Get("attributes").IsObject())
    throw SceneError(m.file, what + " must be an object with an 'attributes' object");
  const tinygltf::Value& attributes = ext->second.Get("attributes");
  auto accessor_of = [&](const char* key) {
    if (!attributes.Has(key)) return -1;
    const tinygltf::Value& v = attributes.Get(key);
    const int index = json_index(v);
    if (index < 0) throw SceneError(m.file, what + " " + key + " must be an accessor index");
    return index;
  };
  const int t = accessor_of("TRANSLATION"), r = accessor_of("ROTATION"), s = accessor_of("SCALE");
  if (t < 0 && r < 0 && s < 0)
    throw SceneError(m.file, what + " has none of TRANSLATION, ROTATION and SCALE");
  std::vector<glm::vec3> translations, scales;
  std::vector<glm::vec4> rotations;
  // With KHR_mesh_quantization, TRANSLATION and SCALE may be integers as POSITION may.
  if (t >= 0) translations = read_positions(m, t, what + " TRANSLATION");
  if (r >= 0) rotations = read_rotations(m, r, what + " ROTATION");
  if (s >= 0) scales = read_positions(m, s, what + " SCALE");
  const std::size_t count = t >= 0 ? translations.size() : r >= 0 ? rotations.size() : scales.size();
  auto check_count = [&](std::size_t size, int accessor, const char* key) {
    if (accessor >= 0 && size != count)
      throw SceneError(m.file, what + " " + key + " has " + std::to_string(size) + " instances but another attribute has " +
                                   std::to_string(count));
  };
  check_count(rotations.size(), r, "ROTATION");
  check_count(scales.size(), s, "SCALE");
  if (count > kMaxInstances)
    throw SceneError(m.file, what + ": " + std::to_string(count) + " instances exceed the limit of " +
                                 std::to_string(kMaxInstances));
  if (mesh_triangles > 0 && count > kMaxInstancedTriangles / mesh_triangles)
    throw SceneError(m.file, what + ": " + std::to_string(count) + " instances of a mesh of up to " +
                                 std::to_string(mesh_triangles) + " triangles exceed the limit of " +
                                 std::to_string(kMaxInstancedTriangles) + " instanced triangles");
  std::vector<glm::dmat4> out;
  out.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::string instance = what + " instance " + std::to_string(k);
    glm::dmat4 transform(1.0);
    if (t >= 0) {
      const glm::dvec3 v(translations[k]);
      if (!finite(glm::dvec4(v, 0.0))) throw SceneError(m.file, instance + ": non-finite TRANSLATION");
      transform = glm::translate(transform, v);
    }
    if (r >= 0) {
      const glm::dvec4 q(rotations[k]);
      const double len = glm::length(q);
      if (!finite(q) || !(len > 0.0)) throw SceneError(m.file, instance + ": ROTATION is not a usable quaternion");
      transform = transform * glm::mat4_cast(glm::dquat(q.w / len, q.x / len, q.y / len, q.z / len));
    }
    if (s >= 0) {
      const glm::dvec3 v(scales[k]);
      if (!finite(glm::dvec4(v, 0.0))) throw SceneError(m.file, instance + ": non-finite SCALE");
      transform = glm::scale(transform, v);
    }
    out.push_back(transform);
  }
  return std::optional<std::vector<glm::dmat4>>(std::move(out));
}

}  // namespace lancer::gltf
