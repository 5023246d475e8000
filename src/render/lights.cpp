#include "render/lights.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/color.h"

namespace lancer {

namespace {

// The distance window the KHR_lights_punctual extension recommends for a finite range.
float range_window(float distance, float range) {
  if (!(range > 0.0f)) return 1.0f;
  const float r = distance / range;
  return std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
}

// The extension's spot falloff: a linear ramp in cos(angle) between the cones, squared.
float spot_falloff(const PunctualLight& light, const glm::vec3& to_point) {
  const float cos_outer = std::cos(light.outer_cone);
  const float cos_inner = std::cos(light.inner_cone);
  const float scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
  const float offset = -cos_outer * scale;
  const float len = glm::length(light.direction);
  if (!(len > 0.0f)) return 0.0f;
  const float cd = glm::dot(light.direction / len, to_point);
  const float t = std::clamp(cd * scale + offset, 0.0f, 1.0f);
  return t * t;
}

}  // namespace

PunctualIncidence illuminate(const PunctualLight& light, const glm::vec3& p) {
  PunctualIncidence in;
  const glm::vec3 power = light.color * light.intensity;
  if (light.type == LightType::Directional) {
    const float len = glm::length(light.direction);
    if (!(len > 0.0f)) return in;
    in.wi = -light.direction / len;
    in.distance = kInfinity;
    in.irradiance = power;
    return in;
  }
  const glm::vec3 d = light.position - p;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f) || !std::isfinite(dist2)) return in;  // at the light: no direction
  in.distance = std::sqrt(dist2);
  in.wi = d / in.distance;
  float scale = range_window(in.distance, light.range) / dist2;
  if (light.type == LightType::Spot) scale *= spot_falloff(light, -in.wi);
  in.irradiance = power * scale;
  return in;
}

AreaLights::AreaLights(const Scene& scene) : light_of_prim_(scene.triangle_count(), -1) {
  double total = 0.0;
  for (std::size_t i = 0; i < scene.triangle_count(); ++i) {
    const Material& m = scene.materials[scene.material_id[i]];
    if (!m.emissive()) continue;
    EmissiveTriangle t;
    t.prim = static_cast<std::uint32_t>(i);
    t.a = scene.triangles.vertex(i, 0);
    t.e1 = scene.triangles.vertex(i, 1) - t.a;
    t.e2 = scene.triangles.vertex(i, 2) - t.a;
    const glm::vec3 n = glm::cross(t.e1, t.e2);
    const float len = glm::length(n);
    t.area = 0.5f * len;
    t.radiance = m.emission();
    const double power = static_cast<double>(t.area) * luminance(t.radiance);
    // Lights too small for float, or with no positive luminance, can never be sampled
    // with a finite pdf: they are left out (they still show when seen directly).
    if (!(len > 0.0f) || !std::isfinite(len) || !(power > 0.0) || !std::isfinite(power)) continue;
    t.normal = n / len;
    total += power;
    light_of_prim_[i] = static_cast<std::int32_t>(lights_.size());
    lights_.push_back(t);
    cdf_.push_back(total);
  }
}

float AreaLights::pick_probability(std::size_t i) const {
  const double prev = i == 0 ? 0.0 : cdf_[i - 1];
  return static_cast<float>((cdf_[i] - prev) / cdf_.back());
}

AreaLightSample AreaLights::sample(float u_pick, float u1, float u2) const {
  const double target = static_cast<double>(u_pick) * cdf_.back();
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), target);
  if (it == cdf_.end()) --it;
  const std::size_t i = static_cast<std::size_t>(it - cdf_.begin());
  const EmissiveTriangle& t = lights_[i];

  // Uniform point on the triangle (Shirley's square-root warp, e.g. pbrt-v4 SampleUniformTriangle).
  const float su = std::sqrt(u1);
  const float s = su * (1.0f - u2);
  const float r = su * u2;
  AreaLightSample out;
  out.point = t.a + s * t.e1 + r * t.e2;
  out.normal = t.normal;
  out.radiance = t.radiance;
  out.pdf_area = pick_probability(i) / t.area;
  out.prim = t.prim;
  out.b1 = s;
  out.b2 = r;
  return out;
}

float AreaLights::pdf_area(std::uint32_t prim) const {
  if (prim >= light_of_prim_.size() || light_of_prim_[prim] < 0) return 0.0f;
  const auto i = static_cast<std::size_t>(light_of_prim_[prim]);
  return pick_probability(i) / lights_[i].area;
}

}  // namespace lancer
