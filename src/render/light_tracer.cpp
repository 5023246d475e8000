#include "render/light_tracer.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "render/coverage.h"
#include "render/path_rules.h"
#include "render/photon_walk.h"
#include "render/shading_inputs.h"
#include "render/shadow_ray.h"
#include "render/surface.h"
#include "render/surface_bsdf.h"
#include "render/tile_scheduler.h"
#include "simd/splitmix64.h"

namespace lancer {

namespace {

// Light paths are one sampler stream, told apart from pixels (y < 2^14), SPPM's photons
// (0xFFFFFFFF) and the caustic map's (0xFFFFFFFE) by their y.
constexpr std::uint32_t kLightPathStreamY = 0xFFFFFFFDu;

// Roughness below which a lobe may be delta (alpha = roughness^2 < kSmoothAlpha of
// render/microfacet.h, roughness < 0.032), with room.
constexpr float kMaybeSmooth = 0.05f;

// Per image, the least green value a lookup of it can give (roughness is in G): texels are
// 8-bit, and filtering only blends them, so no lookup goes below the smallest. An image of
// one or two channels is grey, its G the grey. Only the images a roughness texture reads are
// scanned (1 for the others, which least_green never asks for), each once.
std::vector<float> least_greens(const Scene& scene) {
  std::vector<float> least(scene.images.size(), 1.0f);
  std::vector<bool> scanned(scene.images.size(), false);
  auto scan = [&](const TextureRef& ref) {
    if (!ref.present() || static_cast<std::size_t>(ref.texture) >= scene.textures.size()) return;
    const int k = scene.textures[static_cast<std::size_t>(ref.texture)].image;
    if (k < 0 || static_cast<std::size_t>(k) >= scene.images.size() || scanned[static_cast<std::size_t>(k)]) return;
    scanned[static_cast<std::size_t>(k)] = true;
    const Image& im = scene.images[static_cast<std::size_t>(k)];
    if (im.channels <= 0 || im.pixels.empty()) return;
    const std::size_t stride = static_cast<std::size_t>(im.channels), green = im.channels >= 3 ? 1 : 0;
    std::uint8_t g = 255;
    for (std::size_t i = green; i < im.pixels.size(); i += stride) g = std::min(g, im.pixels[i]);
    least[static_cast<std::size_t>(k)] = static_cast<float>(g) / 255.0f;
  };
  for (const Material& m : scene.materials) {
    scan(m.metallic_roughness_texture);
    scan(m.clearcoat_roughness_texture);
  }
  return least;
}

float least_green(const Scene& scene, const std::vector<float>& least, const TextureRef& ref) {
  if (!ref.present() || static_cast<std::size_t>(ref.texture) >= scene.textures.size()) return 1.0f;
  const int image = scene.textures[static_cast<std::size_t>(ref.texture)].image;
  return image >= 0 && static_cast<std::size_t>(image) < least.size() ? least[static_cast<std::size_t>(image)] : 1.0f;
}

// Whether material m may scatter by a delta lobe somewhere: a superset of the materials that
// do (a light path ends at the others' surfaces, so a wrong "no" would lose paths the camera
// side weighs as shared). Roughness textures count by their smallest texel: the still life's
// textured metals are rough everywhere, and light paths there would be rays for nothing. A
// roughness that is not a number counts as smooth.
bool may_scatter_delta(const Scene& scene, const std::vector<float>& least, const Material& m) {
  if (m.unlit) return false;
  const bool smooth_base = !(m.roughness * least_green(scene, least, m.metallic_roughness_texture) >= kMaybeSmooth);
  const bool smooth_coat =
      (m.clearcoat > 0.0f || m.clearcoat_texture.present()) &&
      !(m.clearcoat_roughness * least_green(scene, least, m.clearcoat_roughness_texture) >= kMaybeSmooth);
  // A transmission of index about 1 passes light straight through whatever the roughness.
  const bool straight_through =
      (m.transmission > 0.0f || m.transmission_texture.present()) && !(std::abs(m.ior - 1.0f) >= 0.01f);
  return smooth_base || smooth_coat || straight_through;
}

// Whether light and camera paths through material m could take ways the other cannot: a
// single-sided surface (culled from behind) that light passes from its front, by coverage or
// by transmission, where a camera path going the other way meets its back and passes it
// without a vertex; a volume that absorbs (KHR_materials_volume), which a light path leaving
// an emitter inside it does not know it is in. Scenes with such materials keep the camera's
// paths alone. (Opaque single-sided surfaces are handled: a path passing one from behind is
// not shared, path.cpp's crossed_culled and the light side's `ends`.)
bool breaks_reciprocity(const Material& m) {
  const bool passes_light = m.alpha_mode != AlphaMode::Opaque || m.transmission > 0.0f || m.transmission_texture.present();
  const bool absorbs = !is_thin_walled(m) && m.attenuation_distance > 0.0f && std::isfinite(m.attenuation_distance);
  return (culls_back_faces(m) && passes_light) || absorbs;
}

// The lens point's two uniform values for light path `index` at its `bounces`-th surface:
// a hash (splitmix64, Steele et al. 2014), independent of the path's Sobol' values.
glm::vec2 lens_values(std::uint64_t seed, std::uint64_t index, int bounces) {
  auto mix = [](std::uint64_t z) { return splitmix64_mix(z + 0x9E3779B97F4A7C15ull); };
  const std::uint64_t h = mix(mix(seed ^ 0x4C69676874547263ull) ^ index) + static_cast<std::uint64_t>(bounces);
  const std::uint64_t bits = mix(h);
  // 24 bits each: floats in [0, 1).
  return {static_cast<float>(bits >> 40) * 0x1p-24f, static_cast<float>((bits >> 8) & 0xFFFFFFu) * 0x1p-24f};
}

}  // namespace

bool LightTracer::applies(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                          const AreaLights& area_lights) {
  if (!settings.light_traced_caustics || settings.integrator != IntegratorKind::Path) return false;
  if (settings.filter != PixelFilterType::Box || camera.orthographic() || camera.shutter_open()) return false;
  if (settings.max_depth < 2 || area_lights.empty()) return false;
  if (std::any_of(scene.materials.begin(), scene.materials.end(), breaks_reciprocity)) return false;
  const std::vector<float> least = least_greens(scene);
  return std::any_of(scene.materials.begin(), scene.materials.end(),
                     [&](const Material& m) { return may_scatter_delta(scene, least, m); });
}

LightTracer::LightTracer(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                         const AreaLights& area_lights, const RenderSettings& settings)
    : scene_(scene),
      accel_(accel),
      camera_(camera),
      area_lights_(area_lights),
      emission_(scene, area_lights, nullptr, LightEmission::Emitters::TrianglesOnly),
      max_depth_(settings.max_depth),
      seed_(settings.seed),
      has_coverage_(scene_has_coverage(scene)),
      paths_per_pass_((static_cast<std::uint64_t>(settings.width) * static_cast<std::uint64_t>(settings.height) +
                       kPixelsPerLightPath - 1) /
                      kPixelsPerLightPath) {
  const std::vector<float> least = least_greens(scene);
  smooth_.reserve(scene.materials.size());
  for (const Material& m : scene.materials) smooth_.push_back(may_scatter_delta(scene, least, m));
}

double LightTracer::camera_density(const glm::vec3& lens, const glm::vec3& x1, const glm::vec3& ng,
                                   const glm::vec3& w1, float pdf_w1) const {
  // PinholeCamera::importance times the cosine at x1: with w = x1 - lens, r = |w| and
  // a = w.f, |w.ng| / r / (A r^2 (a / r)^3) = |w.ng| / (A a^3). Every path's first bounce
  // asks for this, so it stays free of square roots.
  const glm::vec3 w = x1 - lens;
  const double along = glm::dot(w, camera_.forward());
  const float cos_w1 = std::abs(glm::dot(w1, ng));
  if (!(along > 0.0) || !(cos_w1 > 0.0f)) return 0.0;
  return double(std::abs(glm::dot(w, ng))) * double(pdf_w1) /
         (double(cos_w1) * double(camera_.pixel_area()) * along * along * along);
}

double LightTracer::light_density(std::uint32_t prim, std::uint32_t instance) const {
  if (emission_.empty()) return 0.0;
  const float pdf_area = area_lights_.pdf_area(prim, instance);
  if (!(pdf_area > 0.0f)) return 0.0;
  const Material& m = scene_.materials[scene_.material_id[prim]];
  // LightEmission::sample_area's density: the triangles as one emitter, a side of a
  // two-sided one with probability 1/2, directions by cos / pi.
  const double side = m.double_sided ? 0.5 : 1.0;
  return static_cast<double>(paths_per_pass_) * emission_.pick_probability(0) * double(pdf_area) * side /
         std::numbers::pi;
}

void LightTracer::trace_path(std::uint64_t index, std::vector<Splat>& out, std::uint64_t& rays) const {
  if (emission_.empty()) return;
  auto ends = [&](const Ray& ray, const Hit& hit, int bounces) {
    const Material& m = scene_.materials[scene_.material_id[hit.prim]];
    // A single-sided surface met from behind is passed by the light but would stop the
    // camera's path going the other way (it is opaque, LightTracer::applies): no path
    // through it is shared (the camera side takes those alone, PathIntegrator's
    // crossed_culled).
    if (culls_back_faces(m) && !hits_front_face(scene_, hit.prim, hit.instance, ray)) return true;
    // A first surface that is opaque and never delta: nothing to bring.
    return bounces == 0 && m.alpha_mode == AlphaMode::Opaque && !smooth_[scene_.material_id[hit.prim]];
  };
  walk_photon(scene_, accel_, emission_, index, kLightPathStreamY, seed_, 1.0f, rays, [&](const PhotonVertex& v) {
    // This surface is scattering event bounces + 1 of the whole path, counted from the
    // camera's side; the path tracer stops at max_depth of them.
    if (v.bounces + 1 > max_depth_) return PhotonGoes::Stop;
    if (v.bounces >= 1 && !v.sc.bsdf.is_delta_only()) {
      const CameraPoint cam = camera_.connect(v.si.p, lens_values(seed_, index, v.bounces));
      if (cam.valid) {
        // The surface as the camera's ray meets it: the same triangle and point, seen from
        // the lens (which side it faces, its BSDF towards the camera).
        const glm::vec3 to_lens = cam.lens - v.si.p;
        const float distance = glm::length(to_lens);
        const glm::vec3 wo = to_lens / distance;
        Ray view;
        view.org = cam.lens;
        view.dir = -wo;
        Hit hit = v.hit;
        hit.t = distance;
        const ShadingInputs si = evaluate_shading(scene_, view, hit);
        const float cos_in = std::abs(glm::dot(v.wo, si.ng));
        const float cos_out = std::abs(glm::dot(wo, si.ng));
        // A culled back face (alpha 0 from the camera's side) is no surface to the camera.
        if (!si.unlit && si.alpha > 0.0f && cos_in > 0.0f && cos_out > 0.0f) {
          const SurfaceScattering sc(si, wo);
          const BsdfEval e = sc.evaluate(v.wo);
          const float share = weight(static_cast<double>(paths_per_pass_) * v.start_density,
                                     camera_density(cam.lens, si.p, si.ng, v.wo, e.pdf));
          const glm::vec3 value = v.power * e.f * (share * cos_out * cam.importance / cos_in);
          if (!path_rules::is_black(value) && path_rules::is_finite(value)) {
            // Seen as the camera sees it: from the lens towards x1 (lifted off its surface
            // on the lens's side), so coverage and single-sided surfaces count as for a
            // camera ray.
            const glm::vec3 lifted = offset_ray_origin(si.p, glm::dot(si.ng, wo) >= 0.0f ? si.ng : -si.ng);
            Ray look;
            look.org = cam.lens;
            look.dir = lifted - cam.lens;
            look.tfar = 1.0f - kShadowShorten;
            const float seen = shadow_visibility(scene_, accel_, look, has_coverage_, rays);
            if (seen > 0.0f)
              out.push_back({static_cast<std::uint32_t>(cam.y) * static_cast<std::uint32_t>(camera_.width()) +
                                 static_cast<std::uint32_t>(cam.x),
                             value * seen});
          }
        }
      }
    }
    // On only by delta lobes, and only while a later surface could still be joined.
    if (v.bounces + 2 > max_depth_ || !v.sc.bsdf.has_delta()) return PhotonGoes::Stop;
    return PhotonGoes::DeltaOnly;
  }, ends);
}

std::uint64_t LightTracer::trace_pass(int pass, TileRunner& runner, std::vector<glm::dvec3>& sum) const {
  const std::uint64_t first = static_cast<std::uint64_t>(pass) * paths_per_pass_;
  const std::uint64_t rays = trace_photons_in_chunks(
      runner, static_cast<std::size_t>(paths_per_pass_), chunks_,
      [&](std::size_t i, std::vector<Splat>& out, std::uint64_t& r) { trace_path(first + i, out, r); });
  for (const std::vector<Splat>& chunk : chunks_)
    for (const Splat& s : chunk) sum[s.pixel] += glm::dvec3(s.value);
  return rays;
}

}  // namespace lancer
