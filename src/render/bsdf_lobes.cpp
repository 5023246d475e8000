#include "render/bsdf_lobes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "render/turn.h"

namespace lancer {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
float average(const glm::vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
float unit_clamp(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

// ---- The sheen albedo table -------------------------------------------------------------

// cos_o nodes (j / (kTableCos - 1))^2: uniform in sqrt(cos_o), denser towards grazing
// incidence, where E changes fastest.
constexpr int kTableCos = 64;
constexpr int kTableRoughness = 32;  // roughness nodes from kMinSheenRoughness to 1
constexpr int kTableQuadrature = 96;
// Node 0 of cos_o stands for the limit at grazing incidence, evaluated just above it.
constexpr float kGrazingCos = 1e-4f;

float table_roughness(int k) {
  return kMinSheenRoughness + (1.0f - kMinSheenRoughness) * float(k) / float(kTableRoughness - 1);
}

struct SheenTable {
  std::array<float, kTableCos * kTableRoughness> e{};
  SheenTable() {
    for (int k = 0; k < kTableRoughness; ++k)
      for (int j = 0; j < kTableCos; ++j) {
        const float x = float(j) / float(kTableCos - 1);
        const float c = std::max(x * x, kGrazingCos);
        e[std::size_t(k * kTableCos + j)] = float(sheen_albedo_quadrature(c, table_roughness(k), kTableQuadrature));
      }
  }
};

}  // namespace

// ---- Charlie sheen (Estevez & Kulla 2017; KHR_materials_sheen) --------------------------

float charlie_lambda(float cos_theta, float alpha) {
  // The paper's fit L(x) = a / (1 + b x^c) + d x + e, its coefficients at alpha 0 and 1
  // blended by t = (1 - alpha)^2 (section 3 of the paper; KHR_materials_sheen "Implementation").
  const float t = (1.0f - alpha) * (1.0f - alpha);
  const float a = t * 25.3245f + (1.0f - t) * 21.5473f;
  const float b = t * 3.32435f + (1.0f - t) * 3.82987f;
  const float c = t * 0.16801f + (1.0f - t) * 0.19823f;
  const float d = t * -1.27393f + (1.0f - t) * -1.97760f;
  const float e = t * -4.85967f + (1.0f - t) * -4.32054f;
  const auto l = [&](float x) { return a / (1.0f + b * std::pow(x, c)) + d * x + e; };
  const float x = std::clamp(cos_theta, 0.0f, 1.0f);
  return x < 0.5f ? std::exp(l(x)) : std::exp(2.0f * l(0.5f) - l(1.0f - x));
}

float charlie_sheen(const glm::vec3& wo, const glm::vec3& wi, float alpha) {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
  const glm::vec3 h = reflection_half_vector(wo, wi);
  const float sin2 = h.x * h.x + h.y * h.y;  // sin^2(theta_h), precise near the pole
  const float inv_alpha = 1.0f / alpha;
  const float d = (2.0f + inv_alpha) * std::pow(sin2, 0.5f * inv_alpha) / (2.0f * kPi);
  // D V |cos(wi)| with V = 1 / ((1 + Lambda(wo) + Lambda(wi)) 4 |n.wo| |n.wi|).
  return d / ((1.0f + charlie_lambda(wo.z, alpha) + charlie_lambda(wi.z, alpha)) * 4.0f * wo.z);
}

double sheen_albedo_quadrature(float cos_o, float roughness, int n) {
  const float r = std::clamp(roughness, kMinSheenRoughness, 1.0f);
  const float alpha = r * r;
  const float c = std::clamp(cos_o, 0.0f, 1.0f);
  const glm::vec3 wo(std::sqrt(std::max(0.0f, 1.0f - c * c)), 0.0f, c);
  if (!(c > 0.0f)) return 0.0;
  // Midpoint rule over theta in [0, pi/2] and phi in [0, pi] (the lobe is symmetric about
  // the plane of wo and n, so the half range counts twice). charlie_sheen's terms, with
  // Lambda(wo) once and Lambda(wi) once per ring.
  const float inv_alpha = 1.0f / alpha;
  const float d_norm = (2.0f + inv_alpha) / (2.0f * kPi);
  const float lambda_o = charlie_lambda(c, alpha);
  const double dtheta = 0.5 * std::numbers::pi / n, dphi = std::numbers::pi / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * dtheta;
    const double st = std::sin(theta), ct = std::cos(theta);
    const float scale = 1.0f / ((1.0f + lambda_o + charlie_lambda(float(ct), alpha)) * 4.0f * c);
    double ring = 0.0;
    for (int k = 0; k < n; ++k) {
      const double phi = (k + 0.5) * dphi;
      const glm::vec3 wi(float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct));
      const glm::vec3 h = reflection_half_vector(wo, wi);
      ring += d_norm * std::pow(h.x * h.x + h.y * h.y, 0.5f * inv_alpha);
    }
    sum += ring * scale * st;
  }
  return 2.0 * sum * dtheta * dphi;
}

float sheen_albedo(float cos_o, float roughness) {
  static const SheenTable table;  // filled once, thread-safe (magic static)
  const float x = std::sqrt(std::clamp(cos_o, 0.0f, 1.0f)) * float(kTableCos - 1);
  const float y = (std::clamp(roughness, kMinSheenRoughness, 1.0f) - kMinSheenRoughness) /
                  (1.0f - kMinSheenRoughness) * float(kTableRoughness - 1);
  const int j = std::min(int(x), kTableCos - 2), k = std::min(int(y), kTableRoughness - 2);
  const float fx = x - float(j), fy = y - float(k);
  const auto at = [&](int kk, int jj) { return table.e[std::size_t(kk * kTableCos + jj)]; };
  const float lo = at(k, j) + (at(k, j + 1) - at(k, j)) * fx;
  const float hi = at(k + 1, j) + (at(k + 1, j + 1) - at(k + 1, j)) * fx;
  return lo + (hi - lo) * fy;
}

SheenLobe::SheenLobe(const glm::vec3& color, float roughness)
    : color_(glm::max(color, glm::vec3(0.0f))),
      max_color_(max_component(glm::max(color, glm::vec3(0.0f)))),
      roughness_(std::clamp(roughness, kMinSheenRoughness, 1.0f)),
      alpha_(roughness_ * roughness_) {
  if (!std::isfinite(max_color_)) {  // NaN or infinite colour: no sheen
    color_ = glm::vec3(0.0f);
    max_color_ = 0.0f;
  }
  if (!(roughness_ >= kMinSheenRoughness)) {  // NaN roughness
    roughness_ = 1.0f;
    alpha_ = 1.0f;
  }
}

float SheenLobe::base_scale(const glm::vec3& wo) const {
  if (!exists()) return 1.0f;
  return unit_clamp(1.0f - max_color_ * sheen_albedo(wo.z, roughness_));
}

float SheenLobe::albedo(const glm::vec3& wo) const { return average(color_) * sheen_albedo(wo.z, roughness_); }

BsdfEval SheenLobe::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!(wi.z > 0.0f)) return {};
  return {color_ * charlie_sheen(wo, wi, alpha_), 1.0f / (2.0f * kPi)};
}

std::optional<glm::vec3> SheenLobe::sample(const glm::vec3& /*wo*/, glm::vec2 u) const {
  // Uniform over the hemisphere: z = u.x, density 1 / (2 pi).
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const glm::vec2 cs = turn_cos_sin(u.y);
  return glm::vec3(r * cs.x, r * cs.y, z);
}

// ---- Clearcoat (KHR_materials_clearcoat) -------------------------------------------------

ClearcoatLobe::ClearcoatLobe(float weight, float roughness)
    : weight_(unit_clamp(weight)), ggx_(unit_clamp(roughness) * unit_clamp(roughness)) {}

float ClearcoatLobe::layer_weight(const glm::vec3& wo) const {
  // fresnel_coat's fr with ior 1.5 at |n.V| of the clearcoat normal.
  return weight_ * (kClearcoatF0 + (1.0f - kClearcoatF0) * schlick_weight(wo.z));
}

BsdfEval ClearcoatLobe::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!exists() || ggx_.smooth() || !(wi.z > 0.0f) || !(wo.z > 0.0f)) return {};
  const glm::vec3 h = reflection_half_vector(wo, wi);
  const float d = ggx_.d(h);
  const float lambda_o = ggx_.lambda(wo);
  const float inv_4cos_o = 1.0f / (4.0f * std::max(wo.z, std::numeric_limits<float>::min()));
  // clearcoat Fc D G2 / (4 |n.wo| |n.wi|) times |n.wi|; density D_wo(h) / (4 wo.h) = G1(wo) D / (4 wo.z).
  const float f = layer_weight(wo) * d * inv_4cos_o / (1.0f + lambda_o + ggx_.lambda(wi));
  return {glm::vec3(f), d * inv_4cos_o / (1.0f + lambda_o)};
}

std::optional<glm::vec3> ClearcoatLobe::sample(const glm::vec3& wo, glm::vec2 u) const {
  if (ggx_.smooth()) return glm::vec3(-wo.x, -wo.y, wo.z);
  const glm::vec3 wi = reflect_about(wo, ggx_.sample_visible(wo, u));
  if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface
  return wi;
}

}  // namespace lancer
