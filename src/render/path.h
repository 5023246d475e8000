// Unidirectional path tracing with next-event estimation at every bounce (Kajiya 1986;
// Veach 1997, ch. 9), glTF materials (bsdf.h) and the glTF lights:
//  - emissive triangles, sampled by power (lights.h), and the environment (environment.h)
//    are reached both by light sampling and by BSDF sampling, the two combined by
//    multiple importance sampling with the power heuristic (beta = 2);
//  - KHR_lights_punctual lights are delta lights: light sampling only, one shadow ray each;
//  - KHR_materials_volume: inside a transmissive volume, Beer-Lambert attenuation
//    exp(-sigma_a t) with sigma_a = -ln(attenuationColor) / attenuationDistance;
//  - Russian roulette from the fourth bounce on, with survival probability
//    min(1, sqrt(max throughput component)) (at least 5 %).
// Emission counts on the front side of a triangle only (the side lights.h samples).
// KHR_materials_unlit: the path adds beta * baseColor (either side) and ends; an unlit
// surface is no light (only emissive triangles are sampled), so no MIS weight applies.
// alphaMode is ignored (every triangle is opaque). The background is black unless an
// environment is given.
// With a caustic map (caustic_map.h, `--integrator photon`), every non-delta vertex adds the
// map's estimate, and a path that has scattered off a non-delta lobe and since then only off
// delta lobes counts no emission it reaches (emissive triangles, the environment): that light
// is the map's. Emission seen from the camera through delta bounces only still counts.
// With a light tracer (render/light_tracer.h), a path whose first scattering was by a
// non-delta lobe and every one since by a delta lobe counts an emissive triangle it reaches
// with the MIS weight the light tracer's paths complement; the environment and other
// emission count in full.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "accel/ray_offset_batch.h"
#include "render/caustic_map.h"
#include "render/shadow_ray.h"
#include "render/sobol_batch.h"
#include "render/surface_batch.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/render_settings.h"
#include "render/sobol_sampler.h"
#include "scene/scene.h"

namespace lancer {

class LightTracer;

class PathIntegrator {
 public:
  // Keeps references: all must outlive the integrator. `environment` may be null (black).
  // max_depth: the longest path, in bounces after the camera ray (0: emission seen directly).
  // light_samples: points sampled on the emissive triangles at each bounce (at least 1),
  // each with its shadow ray, combined with the BSDF sample by MIS (Veach 1997, 9.2.4,
  // with n_light = light_samples and n_bsdf = 1).
  // caustics: the caustic photon map the paths add at their non-delta vertices, or null
  // (plain path tracing). isa: the vector passes' instruction set (scalar: none; every ISA
  // gives the same paths). light_tracer: the light paths that share the caustics seen
  // directly with these paths, or null (must outlive the integrator).
  PathIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                 const Environment* environment, int max_depth, int light_samples = 1,
                 const CausticMap* caustics = nullptr, Isa isa = best_supported_isa(),
                 const LightTracer* light_tracer = nullptr);

  // Memory radiance_block reuses from call to call (keep one per thread): once it has
  // held the largest wavefront, the bounce loop allocates nothing.
  struct Scratch;

  // The paths of `count` camera rays with their closest hits (the renderer passes a
  // wavefront: up to kWavefrontBlocks 8x8 blocks of pixels), advanced together bounce by
  // bounce: each bounce shades every live path, then traces the wavefront's shadow rays as
  // one batch and its continuation rays as another (the wavefront formulation of Laine,
  // Karras & Aila 2013, "Megakernels Considered Harmful", on a CPU tile rather than a
  // GPU-wide queue). radiance[i] is the radiance arriving along -rays[i].dir; each path
  // draws from samplers[i] only, so it is the same whatever the wavefront holds.
  // `ray_count` is increased by every ray traced here (not the camera rays).
  // emission_apart (null: none): per ray, whether the emission it meets at its first
  // surface, where that surface is opaque (coverage 1), is estimated elsewhere
  // (render/camera_emission.h) and left out here.
  void radiance_block(const Ray* rays, const Hit* hits, SobolSampler* samplers, int count, glm::vec3* radiance,
                      std::uint64_t& ray_count, Scratch& scratch, const bool* emission_apart = nullptr) const;

  // One path: radiance_block of a block of one.
  glm::vec3 radiance_from_hit(const Ray& ray, const Hit& hit, SobolSampler& sampler, std::uint64_t& rays) const;

 private:
  struct Path;
  // One step of `path` at `hit` of `ray`: adds the emission seen, queues its shadow rays
  // (with what each adds if unoccluded) and, when the path goes on, its continuation ray;
  // or, where the surface's coverage lets the ray through (render/coverage.h), only the
  // ray continued past it. Returns whether the path goes on.
  bool bounce(Path& path, int index, const Ray& ray, const Hit& hit, const SurfaceGeometry& geometry,
              Scratch& scratch, std::uint64_t& ray_count) const;
  // Closest hits of scratch.rays into scratch.hits, and whether scratch.shadows[k] is
  // occluded into scratch.blocked[k]: the rays grouped by octant, big groups as packets.
  void trace_batch(Scratch& scratch) const;
  void trace_shadows(Scratch& scratch) const;
  // The origins of the bounce's shadow and continuation rays (ray_offset_batch.h).
  void solve_origins_of_bounce(Scratch& scratch) const;
  struct OctantGroups;
  template <typename RayOf>
  static void group_by_octant(std::size_t n, RayOf ray_of, OctantGroups& groups);
  // An octant group of fewer rays than this is traced one by one. Measured by the render
  // benchmark's replay of the same rays (AVX-512, best of 3 runs): 8 rather than 16 cut
  // traversal by 10 % on both Cornell boxes and by 3-4 % on balls-3, the bunny and the
  // still life; 4 was no better than 8 within this machine's noise.
  static constexpr std::size_t kMinPacketRays = 8;

  const Scene& scene_;
  const Accelerator& accel_;
  const AreaLights& area_lights_;
  const Environment* environment_;
  int max_depth_;
  int light_samples_;
  bool has_coverage_;  // some material is MASK or BLEND (render/coverage.h)
  const CausticMap* caustics_;
  Isa isa_;  // of the vector passes over a bounce's paths (origins, geometry, sample values)
  const LightTracer* light_tracer_;  // shares the caustics seen directly, or null
};

// The state of one path between bounces.
struct PathIntegrator::Path {
  glm::vec3 L{0.0f}, beta{1.0f};
  int bounces = 0;          // scattering events so far (passing through a surface is none)
  float travelled = 0.0f;   // distance from the last scattering point to the ray's origin
  int crossings = 0;        // surfaces passed since then (render/coverage.h, kMaxCrossings)
  float prev_pdf = 0.0f;   // solid-angle pdf of the BSDF sample that made the ray
  bool prev_delta = true;  // the camera ray, or a delta lobe: no light sampling competes
  bool scattered = false;  // some BSDF sample so far was of a non-delta lobe
  bool first_only = false;  // the first BSDF sample was of a non-delta lobe, every later one delta
  double first_density = 0.0;  // with first_only: LightTracer::camera_density of the path
  glm::vec3 lens{0.0f};        // where its camera ray started
  bool crossed_culled = false;  // since its first scattering it passed a single-sided surface from behind
  bool in_volume = false;
  glm::vec3 sigma_a{0.0f};
  bool emission_apart = false;  // until the first surface: radiance_block's emission_apart
  SobolSampler* sampler = nullptr;
};

// A batch of rays sorted by direction octant (group_by_octant).
struct PathIntegrator::OctantGroups {
  std::vector<Ray> sorted;
  std::vector<std::uint32_t> order;  // sorted[j] is the batch's ray order[j]
  std::size_t start[9] = {};         // octant o: sorted[start[o], start[o + 1])
  std::vector<Hit> hits;             // closest hits of `sorted`
};

struct PathIntegrator::Scratch {
  struct Shadow {
    Ray ray;  // made from `aim` once the bounce's origins are solved
    ShadowAim aim;
    glm::vec3 contribution;  // added to the path's L times the light the ray lets through
    int path;
    std::uint32_t leaf;  // the hit it leaves, in `leaves`
  };
  std::vector<SurfaceOffset> leaves;  // the bounce's hit points, for their rays' origins
  std::vector<Path> paths;          // one per camera ray of the block
  std::vector<int> live, next_live;  // the paths still going, by index
  std::vector<Ray> rays, next_rays;  // their rays, in the order of `live`
  std::vector<std::uint32_t> next_leaves;  // the hit each of next_rays leaves, in `leaves`
  std::vector<OriginRequest> origin_requests;  // the bounce's origins: shadows, then next_rays
  std::vector<glm::vec3> origins;
  std::vector<Hit> hits;
  std::vector<SurfaceGeometry> geometry;  // of `hits`, in vectors (surface_batch.h)
  std::vector<AheadRequest> draws;        // the live paths' bounce values, drawn in vectors (sobol_batch.h)
  std::vector<Shadow> shadows;  // the bounce's shadow rays, path by path in order
  OctantGroups groups;  // the batch being traced, by octant
  // Per shadow ray: occluded, in queue order, then in groups' order (plain bools, as the
  // kernels write them).
  std::unique_ptr<bool[]> blocked;
  std::size_t blocked_capacity = 0;
  PathBatchStats stats;         // added up over every block this scratch served
  CausticMap::Scratch caustic;  // the caustic map's neighbour heap
};

}  // namespace lancer
