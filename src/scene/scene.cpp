#include "scene/scene.h"

#include <algorithm>
#include <vector>

namespace lancer {

std::size_t Scene::drawn_triangle_count() const {
  if (instancing.empty()) return triangles.size();
  std::size_t n = 0;
  for (const Instance& inst : instancing.instances) n += instancing.meshes[inst.mesh].count;
  return n;
}

Bounds3 Scene::bounds() const {
  if (instancing.empty()) return triangles.bounds();
  // The drawn corners' own bounds, as a flattened copy has them (a box of each mesh moved by
  // its instance would be larger, and frame a default camera differently): each mesh's
  // distinct corners once, each instance moving them as the renderer does (drawn_triangle.h).
  std::vector<std::vector<glm::vec3>> corners(instancing.meshes.size());
  for (std::size_t m = 0; m < instancing.meshes.size(); ++m) {
    const MeshRange& r = instancing.meshes[m];
    std::vector<glm::vec3>& c = corners[m];
    c.reserve(3 * std::size_t(r.count));
    for (std::uint32_t i = r.first; i < r.first + r.count; ++i)
      for (int k = 0; k < 3; ++k) c.push_back(triangles.vertex(i, k));
    const auto less = [](const glm::vec3& a, const glm::vec3& b) {
      return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(c.begin(), c.end(), less);
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
  Bounds3 b;
  for (const Instance& inst : instancing.instances)
    for (const glm::vec3& p : corners[inst.mesh]) b.extend(inst.to_world.point(p));
  return b;
}

}  // namespace lancer
