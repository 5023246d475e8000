// Jensen's caustic photon map (1996, "Global Illumination using Photon Maps", sec. 2-3):
// light that reaches a non-delta surface through one or more delta (perfectly specular)
// bounces, estimated from photons with a k-nearest-neighbour density estimate. The path
// tracer adds it at every non-delta vertex and leaves out what it would otherwise find by
// chance (path.h): `--integrator photon`.
//
// Photons leave the lights and scatter as render/photon_walk.h describes (the walk SPPM's
// photons take too), follow delta bounces only, and are stored where
// they first meet a surface whose BSDF is not delta-only, if they have bounced at least once
// (direct light is next-event estimation's). At a surface with both kinds of lobe (a smooth
// coat over a diffuse base) the photon is stored and goes on only if its sample picks a
// delta lobe: the stored photon stands for the non-delta lobes, the path for the delta one.
// Each photon carries power / N, N the photons shot.
//
// Density estimate at x with normal n (Jensen's eq. 6 with the BSDF as the integrator sees it):
//   L(x, wo) = sum over the k - 1 nearest photons of f(wo, wi_p) Phi_p / (pi r_k^2),
// r_k the distance of the k-th nearest: it only sets the disc, since counting it too makes
// the estimate k / (k - 1) too high for a uniform density (the expected value of
// 1 / (pi r_k^2) is density / (k - 1) for a Poisson process). With fewer than k photons
// within the maximum radius R, all of them over pi R^2 (then exact for a uniform density).
// f is the BSDF value times |wi.n| (n its normal) over |wi.ng|, the flux per unit of the true surface's
// area, as SppmIntegrator::gather has it. No cone filter: a box kernel.
// Photons count only if they landed on a surface facing the same way (the dot product of
// the geometric normals, each on its ray's side, at least kCausticNormalCos): the disc is
// meant to lie on one surface, and without the test a floor's estimate near a wall gathers
// the wall's photons (and a thin wall's estimate those of its other side).
//
// Deterministic: photon i draws from its own sampler stream, photons are traced in fixed
// chunks joined in chunk order, the kd-tree and its k nearest are unique (point_kd_tree.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/light_emission.h"
#include "render/point_kd_tree.h"
#include "scene/scene.h"

namespace lancer {

class TileRunner;

// Neighbours (k) without RenderSettings::caustic_k: Jensen's paper uses 50 to 100 for caustics.
inline constexpr int kDefaultCausticK = 50;
inline constexpr int kMaxCausticK = 4096;
// The search radius without RenderSettings::caustic_radius, as a fraction of the scene's
// bounding-sphere radius (LightEmission::scene_radius).
inline constexpr float kCausticRadiusOfScene = 0.05f;
// Minimum cosine between a photon's surface normal and the query point's.
inline constexpr float kCausticNormalCos = 0.9f;
// Photons shot without RenderSettings::photons: this many per pixel, within
// [kMinDefaultCausticPhotons, kMaxDefaultCausticPhotons].
inline constexpr std::int64_t kCausticPhotonsPerPixel = 4;
inline constexpr std::int64_t kMinDefaultCausticPhotons = 200000;
inline constexpr std::int64_t kMaxDefaultCausticPhotons = std::int64_t(1) << 22;
// The most photons a map may be asked to shoot: a stored photon holds about 60 bytes
// (100 while the map is built), and in the worst case every photon shot is stored.
inline constexpr std::int64_t kMaxCausticPhotons = std::int64_t(1) << 24;

inline std::int64_t default_caustic_photons(int width, int height) {
  const std::int64_t n = kCausticPhotonsPerPixel * std::int64_t(width) * std::int64_t(height);
  return n < kMinDefaultCausticPhotons ? kMinDefaultCausticPhotons
                                       : (n > kMaxDefaultCausticPhotons ? kMaxDefaultCausticPhotons : n);
}

// One photon of the map, apart from its position (in the kd-tree).
struct CausticPhoton {
  glm::vec3 wi{0.0f};     // unit, back towards where it came from
  glm::vec3 power{0.0f};  // its flux over the photons shot (W per channel)
  glm::vec3 ng{0.0f};     // the surface's geometric normal on the photon's side
  std::uint32_t bounces = 0;  // delta bounces before it landed (at least 1)
};

class CausticMap {
 public:
  struct Settings {
    std::int64_t photons = 0;  // shot (> 0)
    int k = kDefaultCausticK;  // >= 2
    float max_radius = 0.0f;   // > 0
    int max_depth = 8;         // photons bounce at most max_depth - 1 times (a camera vertex is one more)
    std::uint64_t seed = 0;
  };
  // Shoots the photons (in parallel on `runner`) and builds the kd-tree. Keeps references to
  // scene, accel (used only here) and nothing else. `emission` may be empty: an empty map.
  CausticMap(const Scene& scene, const Accelerator& accel, const LightEmission& emission, const Settings& settings,
             TileRunner& runner);

  std::size_t size() const { return photons_.size(); }  // photons stored
  std::uint64_t rays() const { return rays_; }          // rays traced to build it
  int k() const { return k_; }
  float max_radius() const { return max_radius_; }

  // Neighbour memory for estimate(): keep one per thread, so that queries allocate nothing.
  using Scratch = std::vector<PointKdTree::Neighbour>;

  // The caustic radiance leaving x (geometric normal ng on the viewer's side) towards the
  // viewer, from photons that bounced at most `most_bounces` times. f_cos(wi) gives the
  // BSDF value times |wi.n| (BsdfEval::f), the wedge handled as the caller's BSDF does.
  template <class FCos>
  glm::vec3 estimate(const glm::vec3& x, const glm::vec3& ng, int most_bounces, FCos&& f_cos, Scratch& scratch) const;

  // Traces photon number `index` and appends what it stores (exposed for tests).
  struct Stored {
    glm::vec3 p;
    CausticPhoton photon;
  };
  void trace_photon(std::uint64_t index, std::vector<Stored>& out, std::uint64_t& rays) const;

 private:
  const Scene& scene_;
  const Accelerator& accel_;
  const LightEmission& emission_;
  Settings settings_;
  int k_;
  float max_radius_;
  float inv_photons_;
  PointKdTree tree_;
  std::vector<CausticPhoton> photons_;  // in the tree's slot order
  glm::vec3 lower_{0.0f}, upper_{0.0f};  // the photons' bounds, grown by max_radius
  std::uint64_t rays_ = 0;
};

template <class FCos>
glm::vec3 CausticMap::estimate(const glm::vec3& x, const glm::vec3& ng, int most_bounces, FCos&& f_cos,
                               Scratch& scratch) const {
  if (photons_.empty() || most_bounces < 1) return glm::vec3(0.0f);
  if (x.x < lower_.x || x.y < lower_.y || x.z < lower_.z || x.x > upper_.x || x.y > upper_.y || x.z > upper_.z)
    return glm::vec3(0.0f);
  if (scratch.size() < static_cast<std::size_t>(k_)) scratch.resize(static_cast<std::size_t>(k_));
  PointKdTree::Neighbour* heap = scratch.data();
  const auto most = static_cast<std::uint32_t>(most_bounces);
  const int n = tree_.nearest(x, k_, max_radius_, [&](std::uint32_t slot) {
    const CausticPhoton& ph = photons_[slot];
    return ph.bounces <= most && glm::dot(ph.ng, ng) >= kCausticNormalCos;
  }, heap);
  if (n == 0) return glm::vec3(0.0f);
  // k found: the k-th (the heap's top) sets the radius and is left out; else the whole disc.
  const bool full = n == k_;
  const float r2 = full ? heap[0].d2 : max_radius_ * max_radius_;
  if (!(r2 > 0.0f)) return glm::vec3(0.0f);
  glm::vec3 sum(0.0f);
  for (int i = full ? 1 : 0; i < n; ++i) {
    const CausticPhoton& ph = photons_[heap[i].slot];
    const float cos_g = std::abs(glm::dot(ph.wi, ng));
    if (!(cos_g > 0.0f)) continue;
    sum += ph.power * f_cos(ph.wi) / cos_g;
  }
  return sum / (3.14159265358979323846f * r2);
}

}  // namespace lancer
