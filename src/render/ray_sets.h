// The standard ray sets `lancer rays` writes, so benchmarks run on rays anyone can
// regenerate: camera rays, one diffuse bounce, and shadow rays toward the lights.
//
// Every set is a pure function of (scene, camera, seed): the primary hits are exact
// (Accelerator::intersect's), the random numbers come from PixelSampler keyed by the
// pixel, and the rays are in pixel-tile order whatever the thread count.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/camera.h"
#include "scene/scene.h"

namespace lancer {

enum class RaySet { Primary, Diffuse, Shadow };

std::string_view ray_set_name(RaySet set);
std::optional<RaySet> parse_ray_set(std::string_view name);

// Side of the square pixel tiles the sets are ordered by; image sides must be multiples of it.
inline constexpr int kRayTileSide = 8;

// Pixel (x, y) of ray `index` in tile order: kRayTileSide^2 tiles in row order, each
// tile's rays row-major. `width` must be a positive multiple of kRayTileSide.
std::pair<int, int> tile_order_pixel(std::size_t index, int width);

// One camera ray per pixel through its centre, (x + 0.5, y + 0.5), in tile order. Throws
// std::invalid_argument when the camera's width or height is not a multiple of kRayTileSide.
std::vector<Ray> primary_rays(const PinholeCamera& camera);

// A unit direction in the hemisphere around unit `n`, cosine-weighted (Malley's method:
// uniform on the disk, lifted to the hemisphere; see pbrt-v4 SampleCosineHemisphere).
// u1, u2 in [0, 1); the result's dot with n is strictly positive.
glm::vec3 cosine_hemisphere_direction(const glm::vec3& n, float u1, float u2);

// All the rays of `set` for `camera`'s pixels. Primary: primary_rays(camera). Diffuse and
// shadow: one ray from each primary hit, in the order of the primary rays, pixels whose
// camera ray misses giving none.
//  - diffuse: a cosine-weighted unit direction around the geometric normal facing the
//    camera ray, from the hit offset along that normal (offset_ray_origin), tfar = +inf;
//  - shadow: from the same offset origin toward a point sampled on the emissive triangles
//    (AreaLights), lifted off the light, with tfar just short of it, as the Whitted
//    integrator traces them; without emissive triangles toward the first punctual light
//    (directional: along its direction, unbounded). One ray per hit, even where the light
//    lies behind the surface.
// Random numbers: PixelSampler(x, y, 0, seed). Throws std::invalid_argument for a bad
// image size, and for Shadow when the scene has no light at all.
std::vector<Ray> make_ray_set(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera, RaySet set,
                              std::uint64_t seed);

}  // namespace lancer
