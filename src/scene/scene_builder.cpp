#include "scene/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/scene_error.h"

namespace lancer {

namespace {
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Appends one triangle's three corners to a per-corner array (zeros when `values` is
// null). The array stays empty until the first triangle that has the attribute; it is
// then padded with zeros for the `earlier_corners` before, and reserved as far as the
// triangle arrays are, so that it grows with them instead of doubling on its own.
template <class T>
void append_corners(std::vector<T>& corners, const T* values, std::size_t earlier_corners,
                    std::size_t triangle_capacity) {
  if (!values && corners.empty()) return;
  if (corners.empty()) {
    corners.reserve(3 * triangle_capacity);
    corners.resize(earlier_corners, T(0.0f));
  }
  for (int k = 0; k < 3; ++k) corners.push_back(values ? values[k] : T(0.0f));
}

// Drops the spare capacity of a finished array: readers that cannot count their
// triangles in advance let the arrays grow by doubling, up to twice what they hold.
template <class V>
void shrink(V& v) {
  if (v.capacity() - v.size() > v.size() / 16) v.shrink_to_fit();
}
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
  const std::size_t earlier_corners = 3 * (scene_.triangles.size() - 1);
  const std::size_t capacity = scene_.triangles.x[0].capacity();
  if (attribs.normals) {
    glm::vec3 n[3];
    bool all_valid = true;
    for (int k = 0; k < 3; ++k) {
      // In double: a float normal of tiny components (1e-20) squares to denormals, and its
      // float length would be too far off to make it unit.
      const glm::dvec3 d(attribs.normals[k]);
      const double len = glm::length(d);
      if (!(len > 0.0) || !std::isfinite(len)) {
        ++scene_.stats.zero_normals_repaired;
        all_valid = false;
      } else {
        n[k] = glm::vec3(d / len);
      }
    }
    // A triangle with an unusable corner normal keeps none (zeros, flag clear: shading
    // uses the geometric normal), as scene.h promises, so the array stays empty when no
    // triangle has usable normals.
    append_corners(scene_.normals, all_valid ? n : nullptr, earlier_corners, capacity);
    if (all_valid) flags |= kHasNormals;
  } else {
    append_corners<glm::vec3>(scene_.normals, nullptr, earlier_corners, capacity);
  }
  append_corners(scene_.texcoords, attribs.texcoords, earlier_corners, capacity);
  append_corners(scene_.tangents, attribs.tangents, earlier_corners, capacity);
  append_corners(scene_.texcoords1, attribs.texcoords1, earlier_corners, capacity);
  append_corners(scene_.colors, attribs.colors, earlier_corners, capacity);
  if (attribs.texcoords) flags |= kHasTexcoords;
  if (attribs.tangents) flags |= kHasTangents;
  if (attribs.texcoords1) flags |= kHasTexcoords1;
  if (attribs.colors) flags |= kHasColors;
  scene_.attrib_flags.push_back(flags);
  return true;
}

void SceneBuilder::reserve_more(std::size_t triangles) {
  const std::size_t size = scene_.triangles.size(), capacity = scene_.triangles.x[0].capacity();
  if (size + triangles <= capacity) return;
  const std::size_t n = std::max(size + triangles, capacity + capacity / 2);
  scene_.triangles.reserve(n);
  scene_.material_id.reserve(n);
  scene_.source_triangle_id.reserve(n);
  scene_.attrib_flags.reserve(n);
  // Per-corner arrays in use grow alongside; the others reserve on first use.
  if (!scene_.normals.empty()) scene_.normals.reserve(3 * n);
  if (!scene_.texcoords.empty()) scene_.texcoords.reserve(3 * n);
  if (!scene_.tangents.empty()) scene_.tangents.reserve(3 * n);
  if (!scene_.texcoords1.empty()) scene_.texcoords1.reserve(3 * n);
  if (!scene_.colors.empty()) scene_.colors.reserve(3 * n);
}

void SceneBuilder::finish() {
  for (int k = 0; k < 3; ++k) {
    shrink(scene_.triangles.x[k]);
    shrink(scene_.triangles.y[k]);
    shrink(scene_.triangles.z[k]);
  }
  shrink(scene_.material_id);
  shrink(scene_.source_triangle_id);
  shrink(scene_.attrib_flags);
  shrink(scene_.normals);
  shrink(scene_.texcoords);
  shrink(scene_.tangents);
  shrink(scene_.texcoords1);
  shrink(scene_.colors);
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
