// SurfaceScattering where the shading normal leans (render/shading_inputs.h): a rough
// opaque BSDF bends its normal with the viewer and drops the wedge between the two tangent
// planes (evaluate and sample alike); one that transmits, or has a delta lobe, folds it.
#include "render/surface_bsdf.h"

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

// Draws `count` samples and checks each against the wedge of normal `n`; returns how many
// came back.
int samples_outside_the_wedge(const SurfaceScattering& sc, const glm::vec3& n, int count) {
  SplitMix64 rng(11);
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const std::optional<BsdfSample> bs = sc.sample(u_split, u);
    if (!bs) continue;
    ++kept;
    EXPECT_TRUE(sides_agree(sc.si.ng, n, bs->wi)) << "sample " << i;
  }
  return kept;
}

TEST(SurfaceScattering, RoughMetalBendsItsNormalForAViewWhoseMirrorImageFallsBelow) {
  // ns leans 40 degrees toward +x; a viewer 45 degrees off ng on the other side (-x), 85
  // degrees from ns, has its mirror image about ns 125 degrees off ng: below the surface.
  const ShadingInputs si = leaning_point(40.0f, 0.4f, 1.0f, 0.0f);
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering sc(si, wo);
  ASSERT_TRUE(sc.bends);
  EXPECT_EQ(sc.n, bent_shading_normal(si.ng, si.ns, wo));
  EXPECT_NE(sc.n, si.ns);
  // Its BSDF is the one around the bent normal: the same value as a flat surface whose
  // shading normal is the bent one, for directions outside the wedge.
  ShadingInputs flat = si;
  flat.ns = sc.n;
  flat.tangent = glm::normalize(glm::cross(glm::vec3(0, 1, 0), sc.n));
  const Bsdf around_bent = surface_bsdf(flat);
  int compared = 0, dropped = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const float z = -1.0f + 2.0f * (float(i) + 0.5f) / 64.0f, phi = 2.0f * kPi * (float(j) + 0.5f) / 64.0f;
      const float r = std::sqrt(1.0f - z * z);
      const glm::vec3 wi(r * std::cos(phi), r * std::sin(phi), z);
      const BsdfEval e = sc.evaluate(wi);
      if (!sides_agree(si.ng, sc.n, wi)) {
        ++dropped;
        EXPECT_EQ(e.f, glm::vec3(0.0f));
        EXPECT_EQ(e.pdf, 0.0f);
        continue;
      }
      const BsdfEval expected = around_bent.evaluate(wo, wi);
      EXPECT_NEAR(e.f.x, expected.f.x, 1e-5f * (1.0f + expected.f.x));
      EXPECT_NEAR(e.pdf, expected.pdf, 1e-5f * (1.0f + expected.pdf));
      ++compared;
    }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(dropped, 100) << "the test must see the wedge";
  EXPECT_GT(samples_outside_the_wedge(sc, sc.n, 20000), 10000);
  // What MIS combines: a sample's density and weight are what evaluate gives its direction.
  SplitMix64 rng(12);
  for (int i = 0; i < 1000; ++i) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const std::optional<BsdfSample> bs = sc.sample(u_split, u);
    if (!bs) continue;
    const BsdfEval e = sc.evaluate(bs->wi);
    EXPECT_NEAR(bs->pdf, e.pdf, 1e-4f * e.pdf) << i;
    EXPECT_NEAR(bs->weight.x, e.f.x / e.pdf, 1e-4f * bs->weight.x) << i;
  }
}

TEST(SurfaceScattering, ARoughCoatBendsItsOwnNormalToo) {
  // A rough clearcoat whose normal leans with ns: its lobe is evaluated around its normal
  // bent for the view, as the base's is (Cycles bends each closure's normal).
  ShadingInputs si = leaning_point(40.0f, 0.4f, 1.0f, 0.0f);
  si.clearcoat = 1.0f;
  si.clearcoat_roughness = 0.2f;
  si.clearcoat_normal = si.ns;
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering sc(si, wo);
  ASSERT_TRUE(sc.bends);
  const glm::vec3 coat = bent_shading_normal(si.ng, si.clearcoat_normal, wo);
  const Bsdf bent_coat = surface_bsdf(si, ShadingFrame::from_normal_tangent(sc.n, si.tangent), coat);
  const Bsdf unbent_coat = surface_bsdf(si, ShadingFrame::from_normal_tangent(sc.n, si.tangent), si.clearcoat_normal);
  int differ = 0;
  for (float a : {-80.0f, -60.0f, -30.0f, 0.0f, 20.0f, 50.0f}) {
    const glm::vec3 wi = view(a);
    if (!sides_agree(si.ng, sc.n, wi)) continue;
    const glm::vec3 expected = bent_coat.evaluate(wo, wi).f;
    EXPECT_NEAR(sc.evaluate(wi).f.x, expected.x, 1e-6f + 1e-5f * expected.x) << a;
    differ += std::abs(unbent_coat.evaluate(wo, wi).f.x - expected.x) > 1e-3f * (1.0f + expected.x) ? 1 : 0;
  }
  EXPECT_GT(differ, 0) << "the bent coat must change some value for the test to mean anything";
}

TEST(SurfaceScattering, SeenFromAnotherViewIsTheBsdfThatViewBuilds) {
  // The photon walk's adjoint: the BSDF as a camera at `other` would see it, normal bent
  // for that view.
  const ShadingInputs si = leaning_point(40.0f, 0.4f, 1.0f, 0.0f);
  const SurfaceScattering sc(si, view(10.0f));
  const glm::vec3 other = view(-45.0f);
  const SurfaceScattering from_other(si, other);
  ASSERT_NE(sc.n, from_other.n) << "the two views must bend differently";
  for (float a : {-60.0f, -20.0f, 0.0f, 30.0f, 80.0f}) {
    const glm::vec3 wi = view(a);
    EXPECT_EQ(sc.evaluate_seen_from(other, wi).f, from_other.evaluate(wi).f) << a;
  }
}

TEST(SurfaceScattering, RoughGlassKeepsItsNormalAndFoldsTheWedge) {
  // A rough thin wall that transmits: no bending, and the wedge of ns folded: nothing in it,
  // its value added to its mirror image's, and no sample left in it.
  const ShadingInputs si = leaning_point(40.0f, 0.4f, 0.0f, 1.0f);
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering sc(si, wo);
  EXPECT_FALSE(sc.bends);
  EXPECT_EQ(sc.n, si.ns);
  const Bsdf unfolded = surface_bsdf(si);
  // Below ng but above ns (toward +x, low): in the wedge; its image above both.
  const glm::vec3 wedge = glm::normalize(glm::vec3(1.0f, 0.0f, -0.2f));
  const glm::vec3 image = mirror_through_surface(si, wedge);
  ASSERT_FALSE(sides_agree(si, wedge));
  ASSERT_TRUE(sides_agree(si, image));
  EXPECT_EQ(sc.evaluate(wedge).f, glm::vec3(0.0f));
  BsdfEval both = unfolded.evaluate(wo, image);
  both += unfolded.evaluate(wo, wedge);
  ASSERT_GT(unfolded.evaluate(wo, wedge).f.x, 0.0f) << "the wedge direction must carry light to fold";
  EXPECT_NEAR(sc.evaluate(image).f.x, both.f.x, 1e-6f * both.f.x);
  EXPECT_NEAR(sc.evaluate(image).pdf, both.pdf, 1e-6f * both.pdf);
  EXPECT_GT(samples_outside_the_wedge(sc, si.ns, 20000), 10000);
}

TEST(SurfaceScattering, SmoothPlasticFoldsBecauseItHasADeltaLobe) {
  // A smooth dielectric (a delta reflection over the diffuse base) does not bend: a bent
  // mirror would depend on the viewer.
  const ShadingInputs si = leaning_point(40.0f, 0.0f, 0.0f, 0.0f);
  const SurfaceScattering sc(si, view(-45.0f));
  EXPECT_TRUE(sc.bsdf.has_delta());
  EXPECT_FALSE(sc.bends);
  EXPECT_EQ(sc.n, si.ns);
}

TEST(SurfaceScattering, SmoothMirrorFoldsItsReflectionThroughTheSurface) {
  // A smooth white metal (delta): seen from -x at 45 degrees, its reflection about ns lies
  // below the surface; the sample comes back mirrored through the tangent plane, weight kept.
  const ShadingInputs si = leaning_point(40.0f, 0.0f, 1.0f, 0.0f);
  const glm::vec3 wo = view(-45.0f);
  const SurfaceScattering sc(si, wo);
  EXPECT_FALSE(sc.bends);
  const glm::vec3 reflected = 2.0f * glm::dot(si.ns, wo) * si.ns - wo;
  ASSERT_LT(reflected.z, 0.0f);
  const std::optional<BsdfSample> bs = sc.sample(0.5f, glm::vec2(0.5f));
  ASSERT_TRUE(bs.has_value());
  ASSERT_TRUE(bs->delta);
  EXPECT_NEAR(bs->wi.x, reflected.x, 1e-5f);
  EXPECT_NEAR(bs->wi.y, reflected.y, 1e-5f);
  EXPECT_NEAR(bs->wi.z, -reflected.z, 1e-5f);
}

}  // namespace
}  // namespace lancer
