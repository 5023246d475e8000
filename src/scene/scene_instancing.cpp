#include "scene/scene_instancing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/matrix.hpp>

namespace lancer {

namespace {

double frobenius(const glm::dmat3& m) {
  double s = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) s += m[c][r] * m[c][r];
  return std::sqrt(s);
}

bool finite(const Affine& a) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(a.linear[c][r])) return false;
  return std::isfinite(a.offset.x) && std::isfinite(a.offset.y) && std::isfinite(a.offset.z);
}

template <class V>
void permute(V& values, std::span<const std::uint32_t> order, std::size_t per_triangle) {
  if (values.empty()) return;
  V out;
  out.reserve(values.size());
  for (std::uint32_t old : order)
    for (std::size_t k = 0; k < per_triangle; ++k) out.push_back(values[per_triangle * old + k]);
  values.swap(out);
}

}  // namespace

std::optional<Instance> make_instance(std::uint32_t mesh, const glm::dmat4& world) {
  const glm::dmat3 linear(world);
  const double det = glm::determinant(linear);
  if (!(det != 0.0) || !std::isfinite(det)) return std::nullopt;
  const glm::dmat3 inverse = glm::inverse(linear);
  const double condition = frobenius(linear) * frobenius(inverse);
  if (!(condition <= kMaxInstanceCondition)) return std::nullopt;
  // The two-level accelerator's error bounds assume no transform scales by 2^40 or more
  // (two_level.cpp, in the infinity norm, at most sqrt(3) times the Frobenius norm).
  if (!(frobenius(linear) <= 0x1p38) || !(frobenius(inverse) <= 0x1p38)) return std::nullopt;
  const glm::dvec3 offset(world[3]);
  Instance inst;
  inst.mesh = mesh;
  inst.to_world = Affine{glm::mat3(linear), glm::vec3(offset)};
  inst.to_object = Affine{glm::mat3(inverse), glm::vec3(-(inverse * offset))};
  if (!finite(inst.to_world) || !finite(inst.to_object)) return std::nullopt;
  return inst;
}

std::optional<MotionKey> motion_key(const glm::dmat4& world) {
  if (!make_instance(0, world)) return std::nullopt;
  const glm::dmat3 linear(world);
  // Higham's iteration converges quadratically from any invertible start; the condition
  // number make_instance allows (1e6) needs about 25 steps.
  glm::dmat3 q = linear;
  for (int step = 0; step < 100; ++step) {
    const glm::dmat3 next = 0.5 * (q + glm::transpose(glm::inverse(q)));
    double change = 0.0;
    for (int c = 0; c < 3; ++c) change = std::max(change, glm::length(next[c] - q[c]));
    q = next;
    if (change < 1e-15) break;
  }
  // A mirror: the proper rotation -q, and the reflection kept in the stretch.
  if (glm::determinant(q) < 0.0) q = -q;
  glm::dmat3 stretch = glm::transpose(q) * linear;
  stretch = 0.5 * (stretch + glm::transpose(stretch));  // symmetric up to rounding: exactly
  // A rotation's stretch is the identity but for rounding (about 1e-16), which would survive
  // into float as tiny off-diagonal entries: make it exact, so a rigid motion stays rigid
  // and instance_at interpolates it without a stretch. 2^-30 is far below float's 2^-24.
  double off_identity = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) off_identity = std::max(off_identity, std::fabs(stretch[c][r] - (c == r ? 1.0 : 0.0)));
  if (off_identity <= 0x1p-30) stretch = glm::dmat3(1.0);
  MotionKey key;
  key.translation = glm::vec3(glm::dvec3(world[3]));
  key.rotation = glm::quat(glm::normalize(glm::quat_cast(q)));
  key.stretch = glm::mat3(stretch);
  return key;
}

void reorder_triangles(Scene& scene, std::span<const std::uint32_t> order) {
  const std::size_t n = scene.triangle_count();
  if (order.size() != n) throw std::invalid_argument("reorder_triangles: the order does not list every triangle");
  std::vector<char> seen(n, 0);
  for (std::uint32_t i : order) {
    if (i >= n || seen[i]) throw std::invalid_argument("reorder_triangles: the order is not a permutation");
    seen[i] = 1;
  }
  for (int k = 0; k < 3; ++k) {
    permute(scene.triangles.x[k], order, 1);
    permute(scene.triangles.y[k], order, 1);
    permute(scene.triangles.z[k], order, 1);
  }
  permute(scene.material_id, order, 1);
  permute(scene.source_triangle_id, order, 1);
  permute(scene.attrib_flags, order, 1);
  permute(scene.normals, order, 3);
  permute(scene.texcoords, order, 3);
  permute(scene.tangents, order, 3);
  permute(scene.texcoords1, order, 3);
  permute(scene.colors, order, 3);
}

}  // namespace lancer
