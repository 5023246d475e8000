// The lobes of the glTF metallic-roughness base (bsdf_base.h), one type each, and the
// Fresnel weights they share. BaseBsdf composes them: it chooses a lobe, splits the
// microfacet interface between reflection and transmission, and forms the mixture's density
// for MIS; the formulas of each lobe live here and nowhere else.
//
// They are composed rather than stacked like the layers of bsdf_lobes.h because glTF's
// fresnel_mix couples them: the diffuse and transmitted base are weighted by
// 1 - specular * max(fr) with fr taken at each direction pair's half vector, so the lobes
// share one BaseFresnel and, at a sampled facet normal, one choice between reflecting and
// transmitting (Walter et al. 2007 choose by F).
//
// Conventions: the base's local frame (z = shading normal) with wo mirrored to wo.z > 0 and
// wi mirrored with it; per-wo values in LobeOutgoing. Every lobe has exists() (whether it
// scatters at all, fixed by the material), and eval() returning f * |cos(wi)| and `density`,
// the solid-angle density of wi given that sampling chose this lobe (for interface lobes:
// this branch at the facet normal); BaseBsdf multiplies the density by the lobe's selection
// probability. Interface lobes share the GGX distribution of the material's roughness and
// are delta lobes where it is smooth (ReflectionLobe::smooth(), TransmissionLobe::delta()).
//
// Adding a lobe of the base: one type here with these operations and its tests, one member of
// BaseBsdf, its term in BaseBsdf::eval_local and its branch in BaseBsdf::sample.
#pragma once

#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/fresnel.h"
#include "render/microfacet.h"

namespace lancer {

struct BsdfInputs;

// The colours and Fresnel factors of glTF's layer mixing, shared by every lobe of the base.
class BaseFresnel {
 public:
  // Inputs clamped to their ranges (see bsdf_base.h). `entering`: wo's side is outside.
  BaseFresnel(const BsdfInputs& in, bool entering);

  // fr at cos(wo, h) for the dielectric (Schlick's or the exact curve, see fresnel.h).
  glm::vec3 reflectance(float cos_wo_h) const { return fresnel_.reflectance(cos_wo_h, fresnel_eta_); }
  // The colour that multiplies specular_brdf: metal's conductor_fresnel and the dielectric's
  // specular * fr, mixed by metallic (spec B.2, KHR_materials_specular).
  glm::vec3 specular_tint(float cos_wo_h, const glm::vec3& fr) const;
  // Weight of the dielectric's base (diffuse + transmission): (1 - metallic)(1 - specular max(fr)).
  float base_weight(const glm::vec3& fr) const;

  const glm::vec3& base_color() const { return base_color_; }
  float base_color_average() const { return (base_color_.x + base_color_.y + base_color_.z) * (1.0f / 3.0f); }
  float metallic() const { return metallic_; }
  float specular() const { return specular_; }
  float transmission() const { return transmission_; }
  // Whether the ior is a usable index of refraction (dielectric_f0 < 1).
  bool can_refract() const { return fresnel_.f0_ior() < 1.0f; }
  // Whether the dielectric's specular layer reflects anything at some angle.
  bool dielectric_reflects() const;
  // n(material or far side) / n(wo side); ior on a thin wall, 1 when the ior is unusable.
  float fresnel_eta() const { return fresnel_eta_; }

 private:
  glm::vec3 base_color_;
  float metallic_, specular_, transmission_;
  DielectricFresnel fresnel_;
  float fresnel_eta_ = 1.0f;
};

// What every lobe reads that depends on wo alone (BaseBsdf::outgoing computes it once).
struct LobeOutgoing {
  glm::vec3 lo{0.0f};       // wo, local, lo.z > 0
  float lambda_o = 0.0f;    // Smith Lambda(lo), for rough lobes
  float g1_o = 0.0f;        // Smith G1(lo) = 1 / (1 + lambda_o)
  float inv_4cos_o = 0.0f;  // 1 / (4 lo.z): the reflection lobe's f and density share it
};

struct LobeValue {
  glm::vec3 f{0.0f};     // f * |cos(wi)|
  float density = 0.0f;  // of wi, given this lobe (and branch) was chosen
};

// The dielectric's diffuse base, (1 - transmission) baseColor / pi weighted by fresnel_mix;
// cosine-distributed samples.
class DiffuseLobe {
 public:
  explicit DiffuseLobe(const BaseFresnel& mix);
  bool exists() const { return exists_; }
  // Its albedo estimate at wo from the base's, base = base_weight(fr(n)) * average(baseColor).
  float estimate(const BaseFresnel& mix, float base) const { return base * (1.0f - mix.transmission()); }
  // wi.z > 0; fr at the pair's half vector.
  LobeValue eval(const BaseFresnel& mix, const glm::vec3& wi, const glm::vec3& fr) const;
  static glm::vec3 sample(glm::vec2 u);

 private:
  bool exists_ = false;
};

// Microfacet reflection of metal and dielectric (specular_brdf times specular_tint): GGX with
// the height-correlated Smith G2, sampled by visible normals (Heitz 2018); a mirror when smooth.
class ReflectionLobe {
 public:
  ReflectionLobe(const BaseFresnel& mix, const GgxDistribution& ggx);
  bool exists() const { return exists_; }
  bool smooth() const { return ggx_.smooth(); }
  bool rough() const { return exists_ && !ggx_.smooth(); }
  // Its share of the interface at a facet whose cos(wo, m) and fr are given (at m = n: its
  // albedo estimate, exact for the mirror).
  float weight(const BaseFresnel& mix, float cos_wo_m, const glm::vec3& fr) const;
  // wi.z > 0 with half vector h (as the sum of the pair) and tint = specular_tint there:
  // f * |cos(wi)| = tint D G2 / (4 |n.wo|), density G1(wo) D / (4 |n.wo|) (the visible-normal
  // density times the reflection Jacobian).
  LobeValue eval(const LobeOutgoing& out, const glm::vec3& wi, const HalfVectorSum& h, const glm::vec3& tint) const;
  // The mirror's throughput at wo (smooth lobes only).
  glm::vec3 mirror_throughput(const BaseFresnel& mix, const glm::vec3& wo) const;
  // wi reflected through facet m; nullopt when it lies below the surface.
  static std::optional<glm::vec3> direction(const glm::vec3& wo, const glm::vec3& m);

 private:
  GgxDistribution ggx_;
  bool exists_;
};

// Transmission through a thin wall (KHR_materials_transmission with KHR_materials_volume's
// thicknessFactor 0): the reflection lobe mirrored to the other side, no refraction.
class ThinWallLobe {
 public:
  ThinWallLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled);
  bool exists() const { return exists_; }
  // Smooth walls pass light straight through: a delta lobe exactly as smooth as the reflection.
  bool delta() const { return ggx_.smooth(); }
  // Its share of the interface at facet m (no total internal reflection on a thin wall).
  float weight(const BaseFresnel& mix, const glm::vec3& wo, const glm::vec3& m, const glm::vec3& fr) const;
  // Its albedo estimate at wo from the base's (see DiffuseLobe::estimate).
  float estimate(const BaseFresnel& mix, const glm::vec3& wo, float base) const;
  // The facet normal that sends wo to wi (wi.z < 0): the reflection half vector of wi mirrored.
  std::optional<glm::vec3> facet_normal(const glm::vec3& wo, const glm::vec3& wi) const;
  LobeValue eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi, const glm::vec3& m,
                 const glm::vec3& fr) const;
  std::optional<glm::vec3> direction(const glm::vec3& wo, const glm::vec3& m) const;
  std::optional<glm::vec3> delta_direction(const glm::vec3& wo) const { return -wo; }

 private:
  GgxDistribution ggx_;
  bool exists_;
};

// Refraction at a volume boundary (KHR_materials_volume): the rough dielectric BTDF of Walter,
// Marschner, Li & Torrance 2007 without its Fresnel factor (fresnel_mix supplies it).
class RefractionLobe {
 public:
  // eta = n(far side) / n(wo side).
  RefractionLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled, float eta);
  bool exists() const { return exists_; }
  // Smooth, or index-matched (light passes straight through whatever the roughness).
  bool delta() const { return delta_; }
  // Its share of the interface at facet m; 0 where wo is totally reflected there.
  float weight(const BaseFresnel& mix, const glm::vec3& wo, const glm::vec3& m, const glm::vec3& fr) const;
  // Its albedo estimate at wo from the base's (see DiffuseLobe::estimate): 0 past the critical
  // angle only for a delta lobe (rough facets may still refract).
  float estimate(const BaseFresnel& mix, const glm::vec3& wo, float base) const;
  // Walter et al.'s generalised half vector (eq. 16) of wo and wi (wi.z < 0).
  std::optional<glm::vec3> facet_normal(const glm::vec3& wo, const glm::vec3& wi) const;
  LobeValue eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi, const glm::vec3& m,
                 const glm::vec3& fr) const;
  std::optional<glm::vec3> direction(const glm::vec3& wo, const glm::vec3& m) const;
  std::optional<glm::vec3> delta_direction(const glm::vec3& wo) const;

 private:
  GgxDistribution ggx_;
  float eta_;
  bool exists_, delta_;
};

}  // namespace lancer

#include "render/bsdf_base_lobes-inl.h"
