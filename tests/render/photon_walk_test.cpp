// scatter_photon (render/photon_walk.h): a photon leaving a surface carries, on average, the
// adjoint of what the camera side gathers there, including where the shading normal leans
// and bends with the viewer.
#include "render/photon_walk.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "leaning_normal_support.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr float kPi = 3.14159265358979f;

using test::leaning_point;
using test::view;

// The flux a photon arriving along -wo sends on, per unit of its own: the integral over the
// hemisphere of K(b) |b.ng| / |wo.ng|, K(b) the BSDF as the camera sees it from b
// (SurfaceScattering::evaluate_seen_from), by the midpoint rule in (cos theta, phi), which
// is uniform in solid angle.
double adjoint_albedo(const ShadingInputs& si, const SurfaceScattering& sc, const glm::vec3& wo, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const float z = (float(i) + 0.5f) / float(n), phi = 2.0f * kPi * (float(j) + 0.5f) / float(n);
      const float r = std::sqrt(1.0f - z * z);
      const glm::vec3 b(r * std::cos(phi), r * std::sin(phi), z);
      sum += double(sc.evaluate_seen_from(b, wo).f.x) * double(z);
    }
  return sum * 2.0 * double(kPi) / (double(n) * double(n)) / double(std::abs(glm::dot(wo, si.ng)));
}

// The mean of scatter_photon's factor (red) over 2^18 random sample values, against the
// adjoint's integral: within five standard errors, plus 0.5 % for the midpoint rule across
// the wedges' edges.
void expect_mean_factor_is_the_adjoint_albedo(const ShadingInputs& si, const SurfaceScattering& sc,
                                              const glm::vec3& wo) {
  const double expected = adjoint_albedo(si, sc, wo, 512);
  ASSERT_GT(expected, 1e-3);
  SplitMix64 rng(5);
  const int count = 1 << 18;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < count; ++k) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const std::optional<PhotonScatter> s = scatter_photon(si, sc, wo, u_split, u);
    const double f = s ? double(s->factor.x) : 0.0;
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / count;
  const double standard_error = std::sqrt(std::max(0.0, sum2 / count - mean * mean) / count);
  EXPECT_NEAR(mean, expected, 5.0 * standard_error + 0.005 * expected) << "expected " << expected;
}

// ns leans 40 degrees toward +x and the photon arrives from 45 degrees the other side: the
// BSDF seen from wo bends its normal (SurfaceScattering::bends), and the normal bent for many
// of the directions b it does not draw (its wedge) still reflects toward wo. Drawn by the BSDF
// alone, photons lost 10 % (metal) and 12 % (dielectric) of this flux. Also: a glossy metal
// (a smaller cosine share), a rough clearcoat and a sheen over the base (layered BSDFs whose
// layers bend too), and a normal that does not lean (the BSDF alone, weighed by its adjoint).
TEST(ScatterPhoton, SendsOnTheAdjointsWholeFlux) {
  struct Case {
    const char* name;
    float lean, roughness, metallic;
    bool coat, sheen, bends;
  };
  const Case cases[] = {{"metal", 40.0f, 0.5f, 1.0f, false, false, true},
                        {"dielectric", 40.0f, 0.5f, 0.0f, false, false, true},
                        {"glossy metal", 40.0f, 0.2f, 1.0f, false, false, true},
                        {"coated metal", 40.0f, 0.5f, 1.0f, true, false, true},
                        {"sheen", 40.0f, 0.5f, 0.0f, false, true, true},
                        {"flat dielectric", 0.0f, 0.5f, 0.0f, false, false, false}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ShadingInputs si = leaning_point(c.lean, c.roughness, c.metallic);
    if (c.coat) {
      si.clearcoat = 1.0f;
      si.clearcoat_roughness = 0.3f;
      si.clearcoat_normal = si.ns;
    }
    if (c.sheen) {
      si.sheen_color = glm::vec3(0.5f);
      si.sheen_roughness = 0.5f;
    }
    const glm::vec3 wo = view(-45.0f);
    const SurfaceScattering sc(si, wo);
    ASSERT_EQ(sc.bends, c.bends);
    expect_mean_factor_is_the_adjoint_albedo(si, sc, wo);
  }
}

// A caustic photon (delta_only) goes on only by a delta lobe: never from a bending surface,
// always from a smooth mirror.
TEST(ScatterPhoton, DeltaOnlyPhotonsLeaveByDeltaLobesAlone) {
  const ShadingInputs rough = leaning_point(40.0f, 0.5f, 1.0f), mirror = leaning_point(0.0f, 0.0f, 1.0f);
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering bending(rough, wo), smooth(mirror, wo);
  ASSERT_TRUE(bending.bends);
  SplitMix64 rng(3);
  for (int k = 0; k < 256; ++k) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    EXPECT_FALSE(scatter_photon(rough, bending, wo, u_split, u, true).has_value());
    const std::optional<PhotonScatter> s = scatter_photon(mirror, smooth, wo, u_split, u, true);
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->delta);
  }
}

// The cosine share reaches directions the BSDF seen from wo never draws (its wedge), and every
// direction scatter_photon returns lies on wo's side.
TEST(ScatterPhoton, ABendingSurfaceReachesItsOwnWedge) {
  const ShadingInputs si = leaning_point(40.0f, 0.5f, 1.0f);
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering sc(si, wo);
  ASSERT_TRUE(sc.bends);
  SplitMix64 rng(9);
  int in_wedge = 0;
  for (int k = 0; k < 4096; ++k) {
    const std::optional<PhotonScatter> s =
        scatter_photon(si, sc, wo, rng.uniform(), glm::vec2(rng.uniform(), rng.uniform()));
    if (!s) continue;
    EXPECT_GT(glm::dot(s->wi, si.ng), 0.0f);
    EXPECT_FALSE(s->delta);
    if (!sides_agree(si.ng, sc.n, s->wi)) ++in_wedge;
  }
  EXPECT_GT(in_wedge, 0);
}

}  // namespace
}  // namespace lancer
