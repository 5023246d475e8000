#include "render/bsdf_base_lobes.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/bsdf_base.h"
#include "render/turn.h"

namespace lancer {
namespace {

// |eta - 1| below this refracts as a delta lobe: the transmitted lobe is then at most
// alpha * 1e-3 radians wide, and the generalised half vector wo + eta wi loses its precision.
constexpr float kIndexMatched = 1e-3f;

// Clamp to [0, 1]; NaN becomes 0.
float unit_clamp(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }
glm::vec3 unit_clamp(const glm::vec3& v) { return {unit_clamp(v.x), unit_clamp(v.y), unit_clamp(v.z)}; }

// Whether the transmitted base exists at all: a dielectric part that transmits something
// coloured, through an ior light can pass (any ior on a thin wall, which does not refract).
bool transmits(const BaseFresnel& mix, bool thin_walled) {
  return (mix.can_refract() || thin_walled) && (1.0f - mix.metallic()) * mix.transmission() > 0.0f &&
         base_lobes::max_component(mix.base_color()) > 0.0f;
}

}  // namespace

// ---- BaseFresnel -----------------------------------------------------------------------

BaseFresnel::BaseFresnel(const BsdfInputs& in, bool entering)
    : base_color_(unit_clamp(in.base_color)),
      metallic_(unit_clamp(in.metallic)),
      specular_(unit_clamp(in.specular)),
      transmission_(unit_clamp(in.transmission)),
      fresnel_(in.ior, in.specular_color,
               transmission_ > 0.0f ? DielectricFresnel::Form::Exact : DielectricFresnel::Form::Schlick) {
  // A thin wall has air on both sides: light meets the index ior from either side.
  if (can_refract()) fresnel_eta_ = in.thin_walled || entering ? in.ior : 1.0f / in.ior;
}

bool BaseFresnel::dielectric_reflects() const {
  return (1.0f - metallic_) * specular_ > 0.0f &&
         (fresnel_.form() == DielectricFresnel::Form::Schlick || fresnel_.f0_ior() > 0.0f);
}

// ---- DiffuseLobe -----------------------------------------------------------------------

DiffuseLobe::DiffuseLobe(const BaseFresnel& mix)
    : exists_((1.0f - mix.metallic()) * (1.0f - mix.transmission()) > 0.0f &&
              base_lobes::max_component(mix.base_color()) > 0.0f) {}

glm::vec3 DiffuseLobe::sample(glm::vec2 u) {
  const float r = std::sqrt(u.x);
  const glm::vec2 cs = turn_cos_sin(u.y);
  return {r * cs.x, r * cs.y, std::sqrt(std::max(0.0f, 1.0f - u.x))};
}

// ---- ReflectionLobe --------------------------------------------------------------------

ReflectionLobe::ReflectionLobe(const BaseFresnel& mix, const GgxDistribution& ggx)
    : ggx_(ggx), exists_(mix.metallic() > 0.0f || mix.dielectric_reflects()) {}

glm::vec3 ReflectionLobe::mirror_throughput(const BaseFresnel& mix, const glm::vec3& wo) const {
  return mix.specular_tint(wo.z, mix.reflectance(wo.z));
}

// ---- ThinWallLobe ----------------------------------------------------------------------

ThinWallLobe::ThinWallLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled)
    : ggx_(ggx), exists_(thin_walled && transmits(mix, true)) {}

// ---- RefractionLobe --------------------------------------------------------------------

RefractionLobe::RefractionLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled, float eta)
    : ggx_(ggx),
      eta_(eta),
      exists_(!thin_walled && transmits(mix, false)),
      delta_(ggx.smooth() || std::abs(eta - 1.0f) < kIndexMatched) {}

}  // namespace lancer
