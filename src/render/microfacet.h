// The GGX / Trowbridge-Reitz microfacet distribution and its Smith masking-shadowing,
// in a local shading frame whose z axis is the (macro) normal. All directions are unit
// vectors pointing away from the surface.
//
// - D(m): glTF 2.0 spec, Appendix B.3.2, D = a^2 X+(n.m) / (pi ((n.m)^2 (a^2 - 1) + 1)^2),
//   written with the tangential components of m (for unit m, (n.m)^2 (a^2 - 1) + 1 =
//   a^2 m.z^2 + m.x^2 + m.y^2), which keeps its precision at the tiny angles of sharp lobes.
// - Smith Lambda(w) = (sqrt(1 + a^2 tan^2(theta)) - 1) / 2 (Heitz 2014, "Understanding the
//   Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2)), G1 = 1 / (1 + L).
// - G2: the height-correlated form 1 / (1 + L(wo) + L(wi)) (Heitz 2014, section 6). For a
//   reflection pair, G2 / (4 |n.l| |n.v|) is exactly the V_GGX of the glTF sample renderer
//   (the spec's text gives the separable G1 G1; height-correlated is the more accurate one).
//   For a refraction pair the exact height-correlated form is a Beta function (Heitz 2014,
//   section 6); we use the same 1 / (1 + L + L), as pbrt-v4 does. It keeps G2 <= G1(wo), so
//   no lobe ever returns more energy than it receives.
// - Sampling: the distribution of visible normals D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z,
//   drawn exactly by Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace lancer {

// Below this alpha (= roughness^2) a lobe is treated as perfectly smooth, i.e. as a delta
// lobe. pbrt-v4 uses the same bound ("EffectivelySmooth"): at alpha = 1e-3 the lobe is
// about 0.06 degrees wide, and below it the half vector of a float direction pair is no
// longer accurate enough for D to be evaluated consistently with the sampler.
inline constexpr float kSmoothAlpha = 1e-3f;

class GgxDistribution {
 public:
  explicit GgxDistribution(float alpha) : alpha_(alpha) {}
  float alpha() const { return alpha_; }
  bool smooth() const { return alpha_ < kSmoothAlpha; }

  // D(m) for a unit microfacet normal m; 0 below the macro surface. (Inline, as lambda:
  // several calls per shading point.)
  float d(const glm::vec3& m) const {
    if (m.z <= 0.0f) return 0.0f;
    const float a2 = alpha_ * alpha_;
    const float k = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
    return a2 / (std::numbers::pi_v<float> * k * k);
  }
  // Smith Lambda(w); +infinity for w in the tangent plane.
  float lambda(const glm::vec3& w) const {
    // (sqrt(1 + a^2 tan^2) - 1) / 2 with tan^2 = (x^2 + y^2) / z^2, multiplied through by |z|.
    const float z = std::abs(w.z);
    if (z == 0.0f) return std::numeric_limits<float>::infinity();
    const float root = std::sqrt(z * z + alpha_ * alpha_ * (w.x * w.x + w.y * w.y));
    return 0.5f * (root / z - 1.0f);
  }
  float g1(const glm::vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
  // Height-correlated masking-shadowing of the pair (either side of the surface).
  float g2(const glm::vec3& wo, const glm::vec3& wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

  // Density of visible normals D_wo(m) (per unit solid angle of m); wo.z > 0.
  float visible_pdf(const glm::vec3& wo, const glm::vec3& m) const;
  // A microfacet normal drawn from D_wo (Heitz 2018, section 3); wo.z > 0, u in [0, 1)^2.
  glm::vec3 sample_visible(const glm::vec3& wo, glm::vec2 u) const;

 private:
  float alpha_;
};

// Mirror `wo` about the unit normal `m`.
glm::vec3 reflect_about(const glm::vec3& wo, const glm::vec3& m);

// normalize(a + b) for two unit directions above the surface (a.z, b.z > 0), also where
// they are nearly opposite and grazing: their sum's squared length then underflows, and
// glm::normalize would give NaN; the sum is rescaled first (exactly, by a power of two).
inline glm::vec3 reflection_half_vector(const glm::vec3& a, const glm::vec3& b) {
  glm::vec3 sum = a + b;
  float len2 = glm::dot(sum, sum);
  if (!(len2 >= std::numeric_limits<float>::min())) {
    sum *= 0x1p60f;
    len2 = glm::dot(sum, sum);
  }
  return sum * (1.0f / std::sqrt(len2));
}

// The half vector of a reflection pair left unnormalised, for evaluations that need D and
// cos(wo, h) but not h itself: s = a + b for unit a, b above the surface, rescaled by an exact
// power of two where |s| is tiny (the pair nearly opposite and grazing), len2 = |s|^2. It
// saves normalising h, and lets D's division merge with G2's (ReflectionLobe::eval).
struct HalfVectorSum {
  glm::vec3 s{0.0f};
  float len2 = 0.0f;
  bool rescaled = false;
  // cos(a, h). For exactly unit a and b it is |a + b| / 2, no division; float ones are unit
  // to a few 2^-24, an error that form divides by |a + b|: below |a + b| = 1/2 (the pair more
  // than 151 degrees apart) cos is taken as a.s / |s|, so the error stays below 1e-6.
  float cos_with(const glm::vec3& a) const {
    return len2 >= 0.25f && !rescaled ? 0.5f * std::sqrt(len2) : glm::dot(a, s) / std::sqrt(len2);
  }
  glm::vec3 unit() const { return s * (1.0f / std::sqrt(len2)); }
};

inline HalfVectorSum reflection_half_sum(const glm::vec3& a, const glm::vec3& b) {
  HalfVectorSum h;
  h.s = a + b;
  h.len2 = glm::dot(h.s, h.s);
  if (!(h.len2 >= 0x1p-20f)) {  // brought to a largest component in [1, 2), exactly
    const float m = std::max(std::abs(h.s.x), std::max(std::abs(h.s.y), std::abs(h.s.z)));
    if (!(m > 0.0f) || !std::isfinite(m)) return h;
    const int e = std::ilogb(m);
    h.s = glm::vec3(std::ldexp(h.s.x, -e), std::ldexp(h.s.y, -e), std::ldexp(h.s.z, -e));
    h.len2 = glm::dot(h.s, h.s);
    h.rescaled = true;
  }
  return h;
}

// Refract `wo` (on the side m points to, wo.m > 0) through the interface with normal m;
// eta = n(far side) / n(wo side). nullopt on total internal reflection.
std::optional<glm::vec3> refract_about(const glm::vec3& wo, const glm::vec3& m, float eta);

// The microfacet normal that refracts wo into wi (wo.z > 0 > wi.z): the generalised half
// vector of Walter et al. 2007 (eq. 16), normalize(wo + eta wi) oriented to z > 0.
// nullopt when no facet facing both directions correctly exists (wo.h <= 0 or wi.h >= 0)
// or the pair is degenerate (eta = 1 and wi = -wo).
std::optional<glm::vec3> refraction_half_vector(const glm::vec3& wo, const glm::vec3& wi, float eta);

}  // namespace lancer
