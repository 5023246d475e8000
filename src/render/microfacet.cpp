#include "render/microfacet.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "render/turn.h"

namespace lancer {

float GgxDistribution::visible_pdf(const glm::vec3& wo, const glm::vec3& m) const {
  const float wo_m = glm::dot(wo, m);
  if (wo_m <= 0.0f || wo.z <= 0.0f) return 0.0f;
  return g1(wo) * wo_m * d(m) / wo.z;
}

glm::vec3 GgxDistribution::sample_visible(const glm::vec3& wo, glm::vec2 u) const {
  // Heitz 2018, section 3: stretch wo to the configuration where the microsurface is the
  // upper half of a unit sphere (alpha = 1), sample the visible part of that hemisphere's
  // projected disk, and unstretch the normal.
  const glm::vec3 v = glm::normalize(glm::vec3(alpha_ * wo.x, alpha_ * wo.y, wo.z));
  // An orthonormal basis around v (any t1 when v is the pole).
  const float len2 = v.x * v.x + v.y * v.y;
  const glm::vec3 t1 = len2 > 0.0f ? glm::vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t2 = glm::cross(v, t1);
  // A uniform point on the unit disk perpendicular to v ...
  const float r = std::sqrt(u.x);
  const glm::vec2 cs = turn_cos_sin(u.y);
  const float p1 = r * cs.x;
  float p2 = r * cs.y;
  // ... warped so that its density matches the projected area of the visible hemisphere:
  // the half of the disk that is partly hidden shrinks by (1 + v.z) / 2.
  const float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  // Project up onto the hemisphere, then unstretch.
  const float p3 = std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  const glm::vec3 nh = p1 * t1 + p2 * t2 + p3 * v;
  return glm::normalize(glm::vec3(alpha_ * nh.x, alpha_ * nh.y, std::max(0.0f, nh.z)));
}

glm::vec3 reflect_about(const glm::vec3& wo, const glm::vec3& m) { return 2.0f * glm::dot(wo, m) * m - wo; }

std::optional<glm::vec3> refract_about(const glm::vec3& wo, const glm::vec3& m, float eta) {
  const float cos_i = glm::dot(wo, m);
  const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return std::nullopt;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  return glm::normalize(-wo / eta + (cos_i / eta - cos_t) * m);
}

std::optional<glm::vec3> refraction_half_vector(const glm::vec3& wo, const glm::vec3& wi, float eta) {
  glm::vec3 h = wo + eta * wi;
  const float len2 = glm::dot(h, h);
  if (!(len2 > 0.0f)) return std::nullopt;
  h /= std::sqrt(len2);
  if (h.z < 0.0f) h = -h;
  if (glm::dot(wo, h) <= 0.0f || glm::dot(wi, h) >= 0.0f) return std::nullopt;
  return h;
}

}  // namespace lancer
