#include "render/ray_sets.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "accel/ray_offset.h"
#include "render/lights.h"
#include "render/sampler.h"
#include "render/shadow_ray.h"
#include "render/surface.h"

namespace lancer {

namespace {

constexpr float kTwoPi = 6.28318530717958648f;
constexpr std::size_t kTileRays = static_cast<std::size_t>(kRayTileSide) * kRayTileSide;

void check_image_size(int width, int height) {
  if (width <= 0 || height <= 0 || width % kRayTileSide != 0 || height % kRayTileSide != 0)
    throw std::invalid_argument("ray set: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " must be positive multiples of " + std::to_string(kRayTileSide));
}

// The closest hits of `rays`, traced as packets of one tile each, in parallel.
std::vector<Hit> trace_all(const Accelerator& accel, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  const std::size_t packets = (rays.size() + kTileRays - 1) / kTileRays;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, packets), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) {
      const std::size_t first = p * kTileRays;
      const std::size_t count = std::min(kTileRays, rays.size() - first);
      accel.intersect_packet(rays.data() + first, hits.data() + first, static_cast<int>(count));
    }
  });
  return hits;
}

// Where shadow rays go: the area lights, or else the first punctual light.
class ShadowTarget {
 public:
  explicit ShadowTarget(const Scene& scene) : area_(scene) {
    if (area_.empty() && scene.lights.empty())
      throw std::invalid_argument("scene " + scene.source +
                                  " has no light (no emissive triangles and no punctual lights), so it has no "
                                  "shadow rays");
    if (area_.empty()) punctual_ = &scene.lights.front();
  }

  Ray ray_from(const glm::vec3& origin, PixelSampler& sampler) const {
    Ray r;
    r.org = origin;
    if (punctual_ == nullptr) {
      const float u_pick = sampler.next();
      const float u1 = sampler.next();
      const float u2 = sampler.next();
      const AreaLightSample ls = area_.sample(u_pick, u1, u2);
      // Aim at the light point lifted off the light's surface toward its front side.
      r.dir = offset_ray_origin(ls.point, ls.normal) - origin;
      r.tfar = 1.0f - kShadowShorten;
    } else if (punctual_->type == LightType::Directional) {
      const float len = glm::length(punctual_->direction);
      r.dir = len > 0.0f ? -punctual_->direction / len : glm::vec3(0.0f);  // toward the light
      r.tfar = kInfinity;
    } else {
      r.dir = punctual_->position - origin;
      r.tfar = 1.0f - kShadowShorten;
    }
    return r;
  }

 private:
  AreaLights area_;
  const PunctualLight* punctual_ = nullptr;
};

}  // namespace

std::string_view ray_set_name(RaySet set) {
  switch (set) {
    case RaySet::Primary: return "primary";
    case RaySet::Diffuse: return "diffuse";
    case RaySet::Shadow: return "shadow";
  }
  return "unknown";
}

std::optional<RaySet> parse_ray_set(std::string_view name) {
  for (RaySet s : {RaySet::Primary, RaySet::Diffuse, RaySet::Shadow})
    if (ray_set_name(s) == name) return s;
  return std::nullopt;
}

std::pair<int, int> tile_order_pixel(std::size_t index, int width) {
  const std::size_t tiles_per_row = static_cast<std::size_t>(width / kRayTileSide);
  const std::size_t tile = index / kTileRays;
  const std::size_t within = index % kTileRays;
  const std::size_t x = tile % tiles_per_row * kRayTileSide + within % kRayTileSide;
  const std::size_t y = tile / tiles_per_row * kRayTileSide + within / kRayTileSide;
  return {static_cast<int>(x), static_cast<int>(y)};
}

std::vector<Ray> primary_rays(const PinholeCamera& camera) {
  check_image_size(camera.width(), camera.height());
  std::vector<Ray> rays(static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height()));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto [x, y] = tile_order_pixel(i, camera.width());
    rays[i] = camera.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
  }
  return rays;
}

glm::vec3 cosine_hemisphere_direction(const glm::vec3& n, float u1, float u2) {
  // Polar map of the disk: r = sqrt(u1) keeps the height sqrt(1 - u1) >= 2^-12 for the
  // 24-bit uniforms of sampler.h, so the direction never lies in the tangent plane.
  const float r = std::sqrt(u1);
  const float phi = kTwoPi * u2;
  const float z = std::sqrt(1.0f - u1);
  // Orthonormal basis around n: Duff et al., "Building an Orthonormal Basis, Revisited",
  // JCGT 6(1), 2017.
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  const glm::vec3 t(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const glm::vec3 s(b, sign + n.y * n.y * a, -n.y);
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * s + z * n);
}

std::vector<Ray> make_ray_set(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera, RaySet set,
                              std::uint64_t seed) {
  std::vector<Ray> primary = primary_rays(camera);
  if (set == RaySet::Primary) return primary;
  if (set != RaySet::Diffuse && set != RaySet::Shadow) throw std::invalid_argument("ray set: unknown set");
  std::optional<ShadowTarget> shadow;
  if (set == RaySet::Shadow) shadow.emplace(scene);

  const std::vector<Hit> hits = trace_all(accel, primary);
  std::vector<Ray> secondary(primary.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, primary.size(), kTileRays),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        if (!hits[i].valid()) continue;
                        const SurfacePoint sp = make_surface_point(scene, primary[i], hits[i]);
                        const auto [x, y] = tile_order_pixel(i, camera.width());
                        PixelSampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), 0, seed);
                        // sp.ng faces the camera ray: the side both kinds of ray leave from.
                        const glm::vec3 origin = offset_ray_origin(sp.p, sp.ng);
                        if (shadow) {
                          secondary[i] = shadow->ray_from(origin, sampler);
                        } else {
                          const float u1 = sampler.next();
                          const float u2 = sampler.next();
                          secondary[i].org = origin;
                          secondary[i].dir = cosine_hemisphere_direction(sp.ng, u1, u2);
                        }
                      }
                    });

  std::size_t kept = 0;
  for (std::size_t i = 0; i < primary.size(); ++i)
    if (hits[i].valid()) secondary[kept++] = secondary[i];
  secondary.resize(kept);
  return secondary;
}

}  // namespace lancer
