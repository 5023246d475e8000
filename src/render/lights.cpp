#include "render/lights.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>

#include "render/color.h"
#include "render/drawn_triangle.h"
#include "render/shading_inputs.h"
#include "render/texture.h"

namespace lancer {

namespace {

// Whether a material's emission varies over a triangle: an emissive texture, or a coverage
// (emission is weighted by it, render/coverage.h). Back-face culling plays no part: the
// estimate looks at the front side.
bool emission_varies(const Scene& scene, const Material& m) {
  return texture_image(scene, m.emissive_texture) != nullptr || m.alpha_mode != AlphaMode::Opaque;
}

// Sub-triangles per edge of the grid that estimates triangle `prim`'s mean emission: about
// one look per texel of the largest texture involved, between 2 and kMaxGrid per edge.
constexpr int kMaxGrid = 32;
constexpr std::size_t kMaxLooks = std::size_t(1) << 22;

int emission_grid(const Scene& scene, const Material& m, std::uint32_t prim) {
  const std::uint8_t flags = prim < scene.attrib_flags.size() ? scene.attrib_flags[prim] : 0;
  double texels = 0.0;
  for (const TextureRef* ref : {&m.emissive_texture, &m.base_color_texture}) {
    const Image* image = texture_image(scene, *ref);
    if (image == nullptr) continue;
    const bool second = ref->texcoord == 1;
    if (!(flags & (second ? kHasTexcoords1 : kHasTexcoords))) continue;  // one texel everywhere
    const std::vector<glm::vec2>& uvs = second ? scene.texcoords1 : scene.texcoords;
    if (uvs.size() < 3 * (std::size_t(prim) + 1)) continue;
    const glm::vec2* uv = &uvs[3 * std::size_t(prim)];
    const glm::vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    // KHR_texture_transform scales UV areas by its determinant.
    const double det = double(ref->transform[0][0]) * ref->transform[1][1] - double(ref->transform[1][0]) * ref->transform[0][1];
    const double area = 0.5 * std::abs(double(d1.x) * d2.y - double(d1.y) * d2.x) * std::abs(det);
    texels = std::max(texels, area * double(image->width) * double(image->height));
  }
  if (!(texels < double(kMaxGrid) * kMaxGrid)) return kMaxGrid;  // NaN too
  return std::clamp(int(std::ceil(std::sqrt(texels))), 2, kMaxGrid);
}

// The mean luminance of what triangle `t` emits towards its front side, texture and
// coverage included, over the centroids of an n x n grid of equal sub-triangles: each
// look is the emission a ray meeting the triangle there would see (evaluate_shading).
double mean_emitted_luminance(const Scene& scene, const EmissiveTriangle& t, int n) {
  Ray ray;
  ray.dir = -t.normal;
  double sum = 0.0;
  int count = 0;
  const float step = 1.0f / float(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j)
      for (int flip = 0; flip < (i + j + 1 < n ? 2 : 1); ++flip) {
        // Upright sub-triangle (i, j) has its centroid at ((i + 1/3), (j + 1/3)) / n, the
        // inverted one beside it at ((i + 2/3), (j + 2/3)) / n.
        const float third = flip == 0 ? 1.0f / 3.0f : 2.0f / 3.0f;
        const float b1 = (float(i) + third) * step, b2 = (float(j) + third) * step;
        ray.org = t.a + b1 * t.e1 + b2 * t.e2 + t.normal;
        const ShadingInputs si = evaluate_shading(scene, ray, Hit{1.0f, t.prim, b1, b2, t.instance});
        sum += luminance(si.emission * si.alpha);
        ++count;
      }
  return sum / count;
}

}  // namespace

float range_window(float distance, float range) {
  if (!(range > 0.0f)) return 1.0f;
  const float r = distance / range;
  return std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
}

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

AreaLights::AreaLights(const Scene& scene) : emissive_rank_(scene.triangle_count(), -1) {
  // Ranks of the emissive triangles within their mesh (the whole scene when one-level).
  const bool instanced = instanced_ = !scene.instancing.empty();
  const std::vector<MeshRange> whole{{0, std::uint32_t(scene.triangle_count())}};
  const std::vector<MeshRange>& meshes = instanced ? scene.instancing.meshes : whole;
  std::vector<std::uint32_t> emissive_in_mesh(meshes.size(), 0);
  for (std::size_t m = 0; m < meshes.size(); ++m)
    for (std::uint32_t i = meshes[m].first; i < meshes[m].first + meshes[m].count; ++i)
      if (scene.materials[scene.material_id[i]].emissive()) emissive_rank_[i] = std::int32_t(emissive_in_mesh[m]++);

  std::vector<EmissiveTriangle> candidates;
  std::vector<int> grid;  // per candidate: emission_grid, 0 for a constant emission
  std::vector<std::size_t> slot_of_candidate;
  std::size_t looks = 0;
  const std::size_t drawings = instanced ? scene.instancing.instances.size() : 1;
  for (std::size_t d = 0; d < drawings; ++d) {
    const std::uint32_t instance = instanced ? std::uint32_t(d) : kNoHit;
    const Instance* inst = scene.instance_transform(instance);
    const MeshRange& mesh = instanced ? meshes[scene.instancing.instances[d].mesh] : whole[0];
    instance_first_.push_back(light_slot_.size());
    light_slot_.resize(light_slot_.size() + emissive_in_mesh[instanced ? scene.instancing.instances[d].mesh : 0], -1);
    for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i) {
      if (emissive_rank_[i] < 0) continue;
      const Material& m = scene.materials[scene.material_id[i]];
      EmissiveTriangle t;
      t.prim = i;
      t.instance = instance;
      const TriangleCorners c = drawn_corners(scene, i, inst);
      t.a = c[0];
      t.e1 = c[1] - t.a;
      t.e2 = c[2] - t.a;
      const glm::vec3 n = drawn_front_normal(c, inst);
      const float len = glm::length(n);
      // Lights too small for float can never be sampled with a finite pdf: they are left
      // out (they still show when seen directly).
      if (!(len > 0.0f) || !std::isfinite(len)) continue;
      t.area = 0.5f * len;
      t.normal = n / len;
      t.radiance = m.emission();
      t.two_sided = m.double_sided;
      const int n_grid = emission_varies(scene, m) ? emission_grid(scene, m, t.prim) : 0;
      looks += std::size_t(n_grid) * std::size_t(n_grid);
      candidates.push_back(t);
      grid.push_back(n_grid);
      slot_of_candidate.push_back(instance_first_.back() + std::size_t(emissive_rank_[i]));
    }
  }
  // However many textured emitters a file has, the estimate looks at most kMaxLooks times.
  const double shrink = looks > kMaxLooks ? std::sqrt(double(kMaxLooks) / double(looks)) : 1.0;
  double total = 0.0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    EmissiveTriangle& t = candidates[k];
    const double mean = grid[k] == 0 ? luminance(t.radiance)
                                     : mean_emitted_luminance(scene, t, std::max(1, int(double(grid[k]) * shrink)));
    t.power = static_cast<double>(t.area) * mean * (t.two_sided ? 2.0 : 1.0);
    // No positive luminance: never sampled (see the class comment).
    if (!(t.power > 0.0) || !std::isfinite(t.power)) continue;
    total += t.power;
    light_slot_[slot_of_candidate[k]] = static_cast<std::int32_t>(lights_.size());
    lights_.push_back(t);
    cdf_.push_back(total);
  }
}

std::int32_t AreaLights::light_index(std::uint32_t prim, std::uint32_t instance) const {
  if (prim >= emissive_rank_.size() || emissive_rank_[prim] < 0) return -1;
  // A one-level scene's triangles have no instance; an instanced scene's always have one.
  if ((instance == kNoHit) != !instanced_) return -1;
  const std::size_t d = instance == kNoHit ? 0 : instance;
  if (d >= instance_first_.size()) return -1;
  return light_slot_[instance_first_[d] + std::size_t(emissive_rank_[prim])];
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
  out.two_sided = t.two_sided;
  out.radiance = t.radiance;
  out.pdf_area = pick_probability(i) / t.area;
  out.prim = t.prim;
  out.instance = t.instance;
  out.b1 = s;
  out.b2 = r;
  return out;
}

float AreaLights::pdf_area(std::uint32_t prim, std::uint32_t instance) const {
  const std::int32_t light = light_index(prim, instance);
  if (light < 0) return 0.0f;
  const auto i = static_cast<std::size_t>(light);
  return pick_probability(i) / lights_[i].area;
}

}  // namespace lancer
