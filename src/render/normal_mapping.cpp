#include "render/normal_mapping.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace lancer {

namespace {

bool usable_length(float len) { return len > 1e-12f && std::isfinite(len); }

}  // namespace

glm::vec4 triangle_tangent(const glm::vec3 p[3], const glm::vec2 uv[3], const glm::vec3& n) {
  const glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const glm::vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
  const float det = d1.x * d2.y - d2.x * d1.y;
  if (det == 0.0f || !std::isfinite(det)) return glm::vec4(0.0f);
  // Inverting the 2x2 UV matrix (Lengyel, "Computing Tangent Space Basis Vectors for an
  // Arbitrary Mesh", 2001).
  const glm::vec3 dpdu = (d2.y * e1 - d1.y * e2) / det;
  const glm::vec3 dpdv = (d1.x * e2 - d2.x * e1) / det;
  glm::vec3 t = dpdu - n * glm::dot(n, dpdu);
  const float len = glm::length(t);
  if (!usable_length(len)) return glm::vec4(0.0f);
  t /= len;
  const float w = glm::dot(glm::cross(n, t), -dpdv) >= 0.0f ? 1.0f : -1.0f;
  return glm::vec4(t, w);
}

glm::vec3 any_tangent(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  return glm::vec3(1.0f + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x);
}

glm::vec3 orthogonal_tangent(const glm::vec3& tangent, const glm::vec3& n) {
  const glm::vec3 t = tangent - n * glm::dot(n, tangent);
  const float len = glm::length(t);
  return usable_length(len) && len > 1e-4f ? t / len : any_tangent(n);
}

glm::vec3 perturb_normal(const glm::vec3& n, const glm::vec4& tangent, const glm::vec3& rgb, float scale) {
  const glm::vec3 tn = (2.0f * rgb - 1.0f) * glm::vec3(scale, scale, 1.0f);
  const glm::vec3 t(tangent);
  const glm::vec3 b = glm::cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
  const glm::vec3 m = tn.x * t + tn.y * b + tn.z * n;
  const float len = glm::length(m);
  return usable_length(len) ? m / len : n;
}

glm::vec3 face_viewer(const glm::vec3& ns, const glm::vec3& ng, const glm::vec3& wo) {
  const float c = glm::dot(ns, wo);
  if (c >= kMinShadingCosine) return ns;
  glm::vec3 p = ns - c * wo;
  if (!(glm::dot(p, ng) > 0.0f)) p = ng - glm::dot(ng, wo) * wo;
  const float len = glm::length(p);
  if (!usable_length(len)) return ng;  // wo == ng: the geometric normal faces the viewer
  return std::sqrt(1.0f - kMinShadingCosine * kMinShadingCosine) * (p / len) + kMinShadingCosine * wo;
}

}  // namespace lancer
