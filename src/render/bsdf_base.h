// The glTF 2.0 metallic-roughness BSDF with KHR_materials_ior, KHR_materials_specular,
// KHR_materials_transmission and KHR_materials_volume's thin / volume switch, for the path tracer.
//
// The model, glTF 2.0 spec Appendix B.2 / B.3.5 plus the extensions (each line names its source):
//   material   = mix(dielectric, metal, metallic)                               (B.2)
//   metal      = specular_brdf * (baseColor + (1 - baseColor)(1 - |V.H|)^5)     (B.3.4 conductor_fresnel)
//   dielectric = specular * fr * specular_brdf                                  (KHR_materials_specular fresnel_mix)
//              + (1 - specular * max(fr)) * base
//   base       = (1 - transmission) * baseColor / pi                           (B.3.3 diffuse_brdf)
//              +      transmission  * baseColor * specular_btdf                 (KHR_materials_transmission)
//   fr         = f0 + (1 - f0) w,  f0 = min(((ior - 1)/(ior + 1))^2 specularColor, 1)  (KHR_materials_ior/specular)
// - specular_brdf = D G2 / (4 |n.l| |n.v|), GGX D with alpha = roughness^2 (B.3.2); G2 is the
//   height-correlated Smith form (see microfacet.h; the spec text shows the separable one).
// - w is Schlick's (1 - |V.H|)^5 (B.3.4) for opaque materials. For transmissive ones
//   (transmission > 0, thin or not) it is the exact dielectric Fresnel curve rescaled to [0, 1]
//   (fresnel.h), so that total internal reflection exists at volume boundaries, a smooth
//   surface reflects F and transmits exactly 1 - F, and the reflection seen from outside
//   does not depend on the thickness.
// - specular_btdf depends on BsdfInputs::thin_walled (KHR_materials_volume, "Extending
//   Materials": thicknessFactor 0, the default, is thin-walled, anything else a volume boundary):
//   * thin-walled (KHR_materials_transmission, "Refraction" and "Transmission BTDF": two
//     surfaces back to back, no macroscopic refraction): the reflection lobe mirrored to the
//     other side, D G2 / (4 |n.wo| |n.wi|) with H_T = normalize(wo + wi - 2 (n.wi) n), the
//     half vector of wo and wi mirrored through the tangent plane. A smooth wall passes light
//     straight through. Both sides face air, so fresnel_mix uses eta = ior from either side
//     (no total internal reflection), and no volume lies behind the wall.
//   * volume boundary (KHR_materials_volume, "Refraction" and "Implementation"): the rough
//     dielectric refraction of Walter, Marschner, Li & Torrance 2007, "Microfacet Models for
//     Refraction through Rough Surfaces" (eq. 21 without its Fresnel factor, which fresnel_mix
//     supplies): |wo.h||wi.h| eta^2 D G2 / (|n.wo||n.wi| (wo.h + eta wi.h)^2) with the
//     generalised half vector h = normalize(wo + eta wi) (eq. 16), eta = n(wi side) / n(wo side).
// - H in fresnel_mix is the half vector of the pair: the reflection half vector for the
//   specular and diffuse terms, H_T or Walter's h for the transmission term. The thin wall
//   uses one Fresnel factor, as fresnel_mix writes it (reflect fr, transmit (1 - fr) baseColor),
//   not the sum over the light bouncing between its two faces.
// - For 0 < metallic < 1 this is B.2's mix of the two BRDFs. B.3.5's shortcut (one F with
//   f0 = lerp(0.04, baseColor, metallic) for both layers) equals it only at metallic 0 or 1.
//
// Conventions and choices:
// - Two-sided: the side of the shading normal that wo lies on is the side the ray came from;
//   `entering` says whether that side is outside (index 1) or inside (index ior). Hence
//   eta = ior when entering, 1 / ior when exiting, whichever way frame.n points (a thin wall
//   ignores `entering`: both sides are outside). transmitted in BsdfSample means "wi on the
//   other side of the shading normal than wo"; the integrator checks the geometric side and
//   does Beer-Lambert (KHR_materials_volume) itself, inside volume boundaries only.
// - No (n_wo / n_wi)^2 radiance scaling across the interface: the BTDF is in the form whose
//   directional albedo is at most 1 in both directions (importance form). A path that enters
//   and leaves a closed object has the factors cancel; an integrator that starts or ends a
//   path inside a medium must apply it.
// - Delta lobes: alpha < kSmoothAlpha = 1e-3 (roughness < ~0.032) makes the reflection and
//   transmission lobes perfect mirror / refraction lobes. An index-matched volume boundary
//   (|eta - 1| < 1e-3) refracts as a delta lobe whatever the roughness (light passes
//   straight through; with ior = 1 the exact Fresnel term is 0, so nothing reflects). A thin
//   wall's transmission is as rough as its reflection, whatever the ior (the extension's
//   formula has no ior in it; its text says the blur is "modulated by" the ior, unquantified).
//   eval() and pdf() never include delta lobes.
// - Sampling picks the interface lobe (microfacet reflection + refraction) or the diffuse
//   lobe with probabilities proportional to estimates of their albedos at wo. The choice is
//   made with u.x, which is then rescaled to [0, 1) within the chosen lobe's interval (as
//   Cycles picks a closure), so that each lobe's directions come from a stratified part of
//   the sampler's 2D set; a separate 1D value would leave each lobe a random subset of it
//   (measured: Cornell box MSE 8 % higher at equal samples). The interface
//   draws a microfacet normal m from the distribution of visible normals (Heitz 2018), then
//   reflects or refracts through m with probabilities proportional to the two terms' weights
//   at m (as Walter et al. 2007 choose by F), so facets beyond the critical angle always
//   reflect; a thin wall's transmitted direction is the reflected one mirrored through the
//   tangent plane. The diffuse lobe is cosine-distributed. A non-delta sample's weight and
//   pdf are those of the whole mixture of non-delta lobes (eval / pdf), so it combines
//   directly with light sampling; a delta sample's probability is exact.
// - Inputs are clamped to their ranges (metallic, roughness, transmission, specular,
//   baseColor in [0, 1], specularColor >= 0); an ior that is not a positive finite number
//   gives F0 = 1 and no refraction (see dielectric_f0).
//
// Known energy loss: the microfacet terms model single scattering only. Light that the
// Smith G2 term masks after one bounce leaves no trace, so the directional albedo of a white
// metal falls with roughness: 0.99 at roughness 0.3, 0.82 at 0.6 and 0.31 at 1.0 (exactly
// 1 - ln 2 there) at normal incidence; rough glass seen from inside loses most (0.42 at
// roughness 1), since light trapped by total internal reflection at the facets is masked
// (Heitz et al. 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model"; Kulla &
// Conty 2017 compensate it). The opposite also happens: the spec's fresnel_mix weights the
// diffuse base by 1 - F(V.H) with the half vector of each diffuse pair, which is reciprocal
// but not energy conserving. A glossy white dielectric at grazing incidence reflects more
// than it receives: albedo 1.57 at roughness 0.1 and 85 degrees, 1.03 at 60 degrees (B.3
// itself warns that its formulation breaks energy conservation). Scaling the base by the
// specular layer's directional albedo (as OpenPBR does) would fix it but is not the spec.
// tests/render/bsdf_sampling_test.cpp measures and prints these albedos per case. A white
// thin wall (transmission 1) loses exactly what a white metal of its roughness loses: each
// facet splits fr + (1 - fr) = 1 between a direction and its mirror image, which share D and
// G2 (tests/render/bsdf_thin_walled_test.cpp).
#pragma once

#include <optional>

#include <glm/vec2.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf_base_lobes.h"
#include "render/fresnel.h"
#include "render/microfacet.h"

namespace lancer {

// Orthonormal shading frame; local z = shading normal.
struct ShadingFrame {
  glm::vec3 t, b, n;
  // Any tangent: the branchless basis of Duff et al. 2017, "Building an Orthonormal Basis,
  // Revisited", JCGT 6(1). n must be unit.
  static ShadingFrame from_normal(const glm::vec3& n);
  // t projected onto the plane of n (Gram-Schmidt); falls back to from_normal when t is
  // (nearly) parallel to n or not finite.
  static ShadingFrame from_normal_tangent(const glm::vec3& n, const glm::vec3& t);
  // The frame of a tangent already unit and orthogonal to n (ShadingInputs' tangent): no
  // second projection, no square root. (Inline, as the two below: every shading point and
  // every direction it evaluates goes through them; out of line each returned its result
  // through memory.)
  static ShadingFrame from_orthonormal(const glm::vec3& n, const glm::vec3& t) { return {t, glm::cross(n, t), n}; }
  glm::vec3 to_local(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// Everything the BSDF needs at one shading point, already evaluated (textures applied by the caller).
struct BsdfInputs {
  glm::vec3 base_color{1.0f};  // linear
  float metallic = 1.0f, roughness = 1.0f;  // glTF perceptual roughness; alpha = roughness^2
  float ior = 1.5f;
  float specular = 1.0f;
  glm::vec3 specular_color{1.0f};
  float transmission = 0.0f;
  // KHR_materials_volume: true for a thin wall (thicknessFactor 0, the glTF default; see
  // is_thin_walled() in shading_inputs.h), false for a volume boundary. The BSDF's own default
  // is the volume boundary.
  bool thin_walled = false;
  // The layers above the base (bsdf.h). KHR_materials_clearcoat: its weight, perceptual
  // roughness and normal (world space, unit; zero: the shading frame's normal).
  float clearcoat = 0.0f, clearcoat_roughness = 0.0f;
  glm::vec3 clearcoat_normal{0.0f};
  // KHR_materials_sheen: linear colour (black: no sheen) and perceptual roughness.
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
};

struct BsdfSample {
  glm::vec3 wi;      // world space, unit
  glm::vec3 weight;  // f * |cos(wi, n)| / pdf  (for delta lobes: the lobe's throughput / its probability)
  float pdf;         // solid-angle pdf; for delta lobes the discrete probability of the lobe, and `delta` is set
  bool delta;
  bool transmitted;  // wi on the other side of the shading surface than wo
  bool layer = false;  // drawn from a layer over the base (the clearcoat's mirror), not the base
};

// A direction's value and density together (what light sampling with MIS needs).
struct BsdfEval {
  glm::vec3 f{0.0f};  // f(wo, wi) * |cos(wi, n)| for the non-delta lobes
  float pdf = 0.0f;   // sample()'s solid-angle density of wi from its non-delta lobes
  BsdfEval& operator+=(const BsdfEval& o) {
    f += o.f;
    pdf += o.pdf;
    return *this;
  }
};

// The glTF metallic-roughness base layer (everything above): the material under the
// KHR_materials_sheen and KHR_materials_clearcoat layers that Bsdf (bsdf.h) stacks on it.
// Its lobes are types of their own (bsdf_base_lobes.h: diffuse, reflection, thin-wall
// transmission, refraction) sharing one BaseFresnel; this type chooses among them, splits
// the interface between reflection and transmission, and forms the mixture's density.
class BaseBsdf {
 private:
  // Probabilities of the two sampling lobes for a given wo (local, wo.z > 0): the interface
  // (microfacet reflection and refraction) and the diffuse base. They sum to 1, or both are
  // 0 when nothing scatters.
  struct LobeChoice {
    float interface = 0.0f, diffuse = 0.0f;
    float total = 0.0f;  // the two albedo estimates' sum before normalising (for Bsdf's lobe choice)
  };

 public:
  // What depends on wo alone, computed once per shading point for all of its light
  // samples' evaluations and its BSDF sample (the overloads below taking one give exactly
  // the results of those taking wo).
  struct Outgoing {
    glm::vec3 wo{0.0f};  // world space, unit
    glm::vec3 lo{0.0f};  // local, mirrored so that lo.z > 0
    bool flipped = false;  // wo was below the shading frame's tangent plane
    bool valid = false;    // false when wo lies in the tangent plane (or is NaN): nothing scatters
    LobeOutgoing local;    // what the lobes read (local.lo == lo)
    LobeChoice lobes;
  };

  // wo-independent setup. `entering`: true when the ray arrives from outside (the side the
  // outward normal points to); ior ratios flip otherwise. Either pass the outward shading
  // normal and entering = (wo on its side), or the normal flipped towards the ray and
  // entering = front_face (SurfacePoint's convention); both give the same result.
  BaseBsdf(const BsdfInputs& in, const ShadingFrame& frame, bool entering);

  // f(wo, wi) * |cos(wi, n)| for the non-delta lobes (0 for delta-only materials). wo, wi unit, pointing away.
  glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const;
  // Density of sample() producing wi from its non-delta lobes (solid angle).
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  // eval() and pdf() at once, for about the cost of one.
  BsdfEval evaluate(const glm::vec3& wo, const glm::vec3& wi) const;
  // nullopt: absorbed, or the drawn direction left the lobe's domain (weight 0).
  // u picks the lobe and the direction in it (see the top of this file); u_split chooses
  // between reflection and refraction where the interface does both.
  std::optional<BsdfSample> sample(const glm::vec3& wo, float u_split, glm::vec2 u) const;

  Outgoing outgoing(const glm::vec3& wo) const;
  BsdfEval evaluate(const Outgoing& out, const glm::vec3& wi) const;
  std::optional<BsdfSample> sample(const Outgoing& out, float u_split, glm::vec2 u) const;

  // Whether sample() reads u_split: only an interface that can both reflect and refract
  // (without transmission any u_split in [0, 1) gives the same sample).
  bool reads_split() const { return has_transmission(); }
  bool has_delta() const;
  bool is_delta_only() const;
  // Whether any lobe that eval() and pdf() see exists (diffuse, rough reflection or refraction).
  bool has_non_delta() const { return diffuse_.exists() || reflection_.rough() || rough_transmission(); }
  // Whether a Lambertian lobe exists (photon mapping keeps its visible points on such surfaces).
  bool has_diffuse() const { return diffuse_.exists(); }
  // The probability that sample(out, ...) picks a delta lobe (the smooth mirror, or a delta
  // transmission), for the integrators that handle the delta and non-delta parts apart.
  float delta_probability(const Outgoing& out) const;
  // Whether sample(out, u_split, u) picks a delta lobe (its direction may still not exist):
  // the event whose probability delta_probability gives.
  bool picks_delta(const Outgoing& out, float u_split, glm::vec2 u) const;
  bool entering() const { return entering_; }
  // n(far side) / n(wo side) for the macroscopic refraction: ior when entering, 1 / ior when
  // exiting, 1 for a thin wall (light leaves into air again, unbent).
  float eta() const { return eta_; }
  bool thin_walled() const { return thin_walled_; }
  const ShadingFrame& frame() const { return frame_; }
  // The albedo estimate (sum over its sampling lobes) at `out`'s wo, 0 when nothing scatters.
  static float albedo_estimate(const Outgoing& out) { return out.lobes.total; }

 private:
  // How the interface lobe splits between reflection and refraction at facet normal m.
  struct InterfaceSplit {
    float reflect = 0.0f, refract = 0.0f;
  };
  LobeChoice choose_lobes(const glm::vec3& wo) const;
  // cos(wo, m) and the Fresnel factor there already computed.
  InterfaceSplit interface_split(const glm::vec3& wo, const glm::vec3& m, float cos_wo_m, const glm::vec3& fr) const;
  InterfaceSplit interface_split_at_normal(const glm::vec3& wo) const;
  // The transmission lobe's share of the interface at m (0 without one).
  float transmission_weight(const glm::vec3& wo, const glm::vec3& m, const glm::vec3& fr) const;
  // The two transmission lobes' terms for wi below the surface, with their density.
  template <class Transmission>
  BsdfEval eval_transmitted(const Transmission& lobe, const Outgoing& out, const glm::vec3& wi) const;
  // A direction through m by the transmission lobe, or its delta direction.
  std::optional<glm::vec3> transmitted_direction(const glm::vec3& wo, const glm::vec3& m) const;
  std::optional<glm::vec3> delta_transmitted_direction(const glm::vec3& wo) const;
  bool has_transmission() const { return thin_wall_.exists() || refraction_.exists(); }
  bool delta_transmission() const {
    return (thin_wall_.exists() && thin_wall_.delta()) || (refraction_.exists() && refraction_.delta());
  }
  bool rough_transmission() const { return has_transmission() && !delta_transmission(); }
  // wo = out.lo, wi local and mirrored with it.
  BsdfEval eval_local(const Outgoing& out, const glm::vec3& wi) const;
  // wi in the local frame, mirrored as out.lo was.
  glm::vec3 to_oriented_local(const Outgoing& out, const glm::vec3& wi) const;

  ShadingFrame frame_;
  BaseFresnel mix_;
  GgxDistribution ggx_;
  float eta_;  // refraction: n(far side) / n(wo side); 1 on a thin wall
  bool entering_;
  bool thin_walled_;
  DiffuseLobe diffuse_;
  ReflectionLobe reflection_;
  ThinWallLobe thin_wall_;
  RefractionLobe refraction_;
  // Whether reflection vs refraction is decided at the macro normal (a delta lobe is
  // involved) rather than at the sampled microfacet normal.
  bool split_at_normal_;
};

}  // namespace lancer
