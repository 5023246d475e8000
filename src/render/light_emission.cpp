#include "render/light_emission.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf_base.h"
#include "render/color.h"
#include "render/drawn_triangle.h"
#include "render/light_sampling.h"
#include "render/ray_sets.h"
#include "render/turn.h"

namespace lancer {

namespace {

constexpr double kPi = std::numbers::pi;

// The largest float below 1: where a remapped uniform must stay.
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// A usable weight: positive and finite (NaN fails both).
bool positive(double w) { return w > 0.0 && std::isfinite(w); }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Uniform on the unit sphere (Archimedes: z uniform in (-1, 1]).
glm::vec3 uniform_sphere(glm::vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const glm::vec2 cs = turn_cos_sin(u.y);
  return {r * cs.x, r * cs.y, z};
}

// A photon's power from its radiance (or intensity) and the inverse of its densities, or
// an invalid photon when that is zero or not finite (a pick probability far below float).
void set_power(EmittedPhoton& photon, const glm::vec3& value, double inverse_pdf) {
  const glm::dvec3 power = glm::dvec3(value) * inverse_pdf;
  photon.power = glm::vec3(power);
  photon.valid = finite(photon.power) && photon.power != glm::vec3(0.0f);
}

}  // namespace

double spot_solid_angle(const PunctualLight& light) {
  if (!(glm::length(light.direction) > 0.0f)) return 0.0;
  // spot_falloff's own float constants: t = clamp((cos - cos_outer) scale, 0, 1), squared.
  const float cos_outer = std::cos(light.outer_cone);
  const float scale = 1.0f / std::max(0.001f, std::cos(light.inner_cone) - cos_outer);
  const double c0 = cos_outer, width = 1.0 / double(scale);  // the ramp: cos in [c0, c0 + width]
  const double span = 1.0 - c0;                              // cos in [c0, 1] is lit
  if (!(span > 0.0)) return 0.0;
  // Integral over cos of t^2: the ramp's (width / 3), or the part of it below cos = 1, plus
  // the fully lit cap beyond it.
  const double integral = span <= width ? span * span * span / (3.0 * width * width) : width / 3.0 + (span - width);
  return 2.0 * kPi * integral;
}

double environment_luminance_integral(const Environment& environment) {
  if (environment.is_constant()) return 4.0 * kPi * luminance(environment.radiance(glm::vec3(0.0f, 1.0f, 0.0f)));
  // Nearest-pixel lookups: each pixel is constant over its patch of the sphere, whose
  // solid angle is (2 pi / W) (cos theta_top - cos theta_bottom).
  const ImageRGB& image = environment.image();
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y) {
    const double solid_angle = 2.0 * kPi / image.width *
                               (std::cos(kPi * y / image.height) - std::cos(kPi * (y + 1) / image.height));
    double row = 0.0;
    for (int x = 0; x < image.width; ++x) row += luminance(image.at(x, y));
    sum += row * solid_angle;
  }
  return sum;
}

LightEmission::LightEmission(const Scene& scene, const AreaLights& area_lights, const Environment* environment,
                             Emitters emitters)
    : scene_(scene), area_lights_(area_lights), environment_(emitters == Emitters::All ? environment : nullptr) {
  const Bounds3 bounds = scene.bounds();
  if (!bounds.empty()) {
    // The bounding sphere, a little enlarged so the disc distant light enters through lies
    // strictly outside the scene whatever the rounding of the centre.
    center_ = bounds.center();
    const glm::vec3 far = glm::max(glm::abs(bounds.lo), glm::abs(bounds.hi));
    const float coordinate = std::max(far.x, std::max(far.y, far.z));
    radius_ = 0.5f * glm::length(bounds.extent()) * (1.0f + 0x1p-10f) + coordinate * 0x1p-20f;
    if (!std::isfinite(radius_)) radius_ = 0.0f;
  }
  const double disc_area = kPi * double(radius_) * double(radius_);

  auto add = [&](const Emitter& e) {
    if (!positive(e.weight)) return;  // emits nothing: never picked
    emitters_.push_back(e);
    total_ += e.weight;
    cdf_.push_back(total_);
  };

  // Emissive triangles, one emitter: AreaLights' power is emitted power / pi.
  double area_power = 0.0;
  for (std::size_t i = 0; i < area_lights.size(); ++i) area_power += area_lights.light(i).power;
  add({Kind::Area, 0, kPi * area_power, glm::vec3(0.0f), 0.0f});

  const std::size_t punctual = emitters == Emitters::All ? scene.lights.size() : 0;
  for (std::size_t i = 0; i < punctual; ++i) {
    const PunctualLight& light = scene.lights[i];
    const double intensity = luminance(light.color * light.intensity);
    Emitter e;
    e.light = static_cast<std::uint32_t>(i);
    const float len = glm::length(light.direction);
    if (len > 0.0f && std::isfinite(len)) e.axis = light.direction / len;
    switch (light.type) {
      case LightType::Point:
        e.kind = Kind::Point;
        e.weight = finite(light.position) ? 4.0 * kPi * intensity : 0.0;
        break;
      case LightType::Spot:
        e.kind = Kind::Spot;
        e.one_minus_cos = 1.0f - std::cos(light.outer_cone);  // the cone spot_falloff lights
        e.weight = finite(light.position) && e.axis != glm::vec3(0.0f) ? intensity * spot_solid_angle(light) : 0.0;
        break;
      case LightType::Directional:
        e.kind = Kind::Directional;
        e.weight = e.axis != glm::vec3(0.0f) ? disc_area * intensity : 0.0;
        break;
    }
    add(e);
  }

  if (environment_ != nullptr)
    add({Kind::Environment, 0, disc_area * environment_luminance_integral(*environment_), glm::vec3(0.0f), 0.0f});
}

EmittedPhoton LightEmission::sample(float u_pick, glm::vec2 u_pos, glm::vec2 u_dir) const {
  const double target = double(u_pick) * total_;
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), target);
  if (it == cdf_.end()) --it;
  const std::size_t i = static_cast<std::size_t>(it - cdf_.begin());
  const Emitter& e = emitters_[i];
  const double p_pick = e.weight / total_;
  switch (e.kind) {
    case Kind::Area: {
      // u_pick again, stretched over the emitter's own share, for AreaLights' pick.
      const double lo = i == 0 ? 0.0 : cdf_[i - 1];
      const float u = std::clamp(float((target - lo) / e.weight), 0.0f, kOneMinusEpsilon);
      return sample_area(u, u_pos, u_dir, p_pick);
    }
    case Kind::Point:
    case Kind::Spot:
      return sample_punctual(e, u_dir, p_pick);
    case Kind::Directional: {
      const PunctualLight& light = scene_.lights[e.light];
      return sample_distant(e.axis, light.color * light.intensity, u_pos, p_pick);
    }
    case Kind::Environment: {
      const EnvSample s = environment_->sample(u_dir);
      if (!(s.pdf > 0.0f)) return {};
      // The sample looks toward the environment; the photon travels the other way.
      return sample_distant(-s.dir, s.radiance / s.pdf, u_pos, p_pick);
    }
  }
  return {};
}

EmittedPhoton LightEmission::sample_area(float u_pick, glm::vec2 u_pos, glm::vec2 u_dir, double p_pick) const {
  EmittedPhoton photon;
  const AreaLightSample s = area_lights_.sample(u_pick, u_pos.x, u_pos.y);
  if (!(s.pdf_area > 0.0f)) return photon;
  // A two-sided emitter: either side with probability 1/2, u_dir.x stretched back to [0, 1).
  glm::vec3 n = s.normal;
  double p_side = 1.0;
  if (s.two_sided) {
    p_side = 0.5;
    if (u_dir.x < 0.5f) {
      u_dir.x *= 2.0f;
    } else {
      n = -n;
      u_dir.x = 2.0f * u_dir.x - 1.0f;
    }
  }
  // Cosine-distributed about the emitting side's normal (density cos / pi, strictly inside
  // the hemisphere), so Le |cos| / (p_pos p_dir) is Le pi / p_pos.
  const glm::vec3 dir = cosine_hemisphere_direction(n, u_dir.x, u_dir.y);
  if (!(glm::dot(dir, n) > 0.0f)) return photon;
  photon.ray.dir = dir;
  photon.ray.org = leaving_offset(scene_, s.point, n, s.prim, s.instance, 0.0f).origin(dir);
  set_power(photon, area_light_radiance(scene_, s, dir), kPi / (p_pick * double(s.pdf_area) * p_side));
  photon.start_density = p_pick * double(s.pdf_area) * p_side / kPi;
  return photon;
}

EmittedPhoton LightEmission::sample_punctual(const Emitter& e, glm::vec2 u_dir, double p_pick) const {
  const PunctualLight& light = scene_.lights[e.light];
  const glm::vec3 intensity = light.color * light.intensity;
  EmittedPhoton photon;
  photon.ray.org = light.position;
  photon.range = light.range;
  if (e.kind == Kind::Point) {
    photon.ray.dir = uniform_sphere(u_dir);
    set_power(photon, intensity, 4.0 * kPi / p_pick);
    return photon;
  }
  // A spot: uniform in solid angle over its outer cone, cos theta uniform in
  // [1 - one_minus_cos, 1]; sin^2 = (1 - cos)(1 + cos) keeps small cones accurate.
  const float one_minus_cos = u_dir.x * e.one_minus_cos;
  const float sin_theta = std::sqrt(std::max(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  const glm::vec2 cs = turn_cos_sin(u_dir.y);
  const glm::vec3 local(sin_theta * cs.x, sin_theta * cs.y, 1.0f - one_minus_cos);
  photon.ray.dir = glm::normalize(ShadingFrame::from_normal(e.axis).to_world(local));
  // The very falloff illuminate() applies toward this direction.
  const float falloff = spot_falloff(light, photon.ray.dir);
  set_power(photon, intensity * falloff, 2.0 * kPi * double(e.one_minus_cos) / p_pick);
  return photon;
}

EmittedPhoton LightEmission::sample_distant(const glm::vec3& dir, const glm::vec3& radiance_over_pdf, glm::vec2 u_pos,
                                            double p_pick) const {
  // Uniform on the disc of radius R facing the light, tangent to the scene's bounding
  // sphere on the light's side: density 1 / (pi R^2).
  EmittedPhoton photon;
  const ShadingFrame frame = ShadingFrame::from_normal(dir);
  const float r = radius_ * std::sqrt(u_pos.x);
  const glm::vec2 cs = turn_cos_sin(u_pos.y);
  photon.ray.dir = dir;
  photon.ray.org = center_ - radius_ * dir + frame.to_world(glm::vec3(r * cs.x, r * cs.y, 0.0f));
  set_power(photon, radiance_over_pdf, kPi * double(radius_) * double(radius_) / p_pick);
  return photon;
}

}  // namespace lancer
