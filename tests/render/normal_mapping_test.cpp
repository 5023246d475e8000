// Tangent frames from UVs, normal-map perturbation and the viewer-side rule, on single
// triangles with known answers.
#include "render/normal_mapping.h"

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

namespace lancer {
namespace {

void expect_vec_near(const glm::vec3& a, const glm::vec3& b, float tol, const char* what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

// The triangle (0,0,0), (1,0,0), (0,1,0) in z = 0, front side +z.
const glm::vec3 kCorners[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
const glm::vec3 kUp(0, 0, 1);

TEST(TriangleTangent, StandardGltfMappingIsRightHanded) {
  // Image upright on the triangle: u along +x, v (downwards in the image) along -y.
  const glm::vec2 uv[3] = {{0, 1}, {1, 1}, {0, 0}};
  const glm::vec4 t = triangle_tangent(kCorners, uv, kUp);
  expect_vec_near(glm::vec3(t), {1, 0, 0}, 1e-6f, "T = dP/du");
  EXPECT_EQ(t.w, 1.0f) << "B = cross(N, T) = +y, the image's up";
}

TEST(TriangleTangent, MirroredUIsLeftHanded) {
  const glm::vec2 uv[3] = {{1, 1}, {0, 1}, {1, 0}};  // u along -x, v along -y
  const glm::vec4 t = triangle_tangent(kCorners, uv, kUp);
  expect_vec_near(glm::vec3(t), {-1, 0, 0}, 1e-6f, "T = dP/du");
  EXPECT_EQ(t.w, -1.0f) << "B = -cross(N, T) = +y is still the image's up";
}

TEST(TriangleTangent, UpsideDownImageIsLeftHanded) {
  const glm::vec2 uv[3] = {{0, 0}, {1, 0}, {0, 1}};  // v along +y: the image's up is -y
  const glm::vec4 t = triangle_tangent(kCorners, uv, kUp);
  expect_vec_near(glm::vec3(t), {1, 0, 0}, 1e-6f, "T = dP/du");
  EXPECT_EQ(t.w, -1.0f);
}

TEST(TriangleTangent, IsOrthogonalToATiltedShadingNormal) {
  const glm::vec2 uv[3] = {{0, 1}, {2, 1.5f}, {0.5f, -1}};  // sheared and scaled
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
  const glm::vec4 t = triangle_tangent(kCorners, uv, n);
  EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(glm::vec3(t), n), 0.0f, 1e-6f);
  // dP/du solves e1 = dP/du du1 + dP/dv dv1 and e2 = dP/du du2 + dP/dv dv2.
  // Per coordinate k, A (dP/du_k, dP/dv_k) = (e1_k, e2_k) with A's rows d1, d2.
  const glm::vec3 e1 = kCorners[1] - kCorners[0], e2 = kCorners[2] - kCorners[0];
  const glm::mat2 inverse_a = glm::inverse(glm::transpose(glm::mat2(uv[1] - uv[0], uv[2] - uv[0])));
  glm::vec3 dpdu;
  for (int k = 0; k < 3; ++k) dpdu[k] = (inverse_a * glm::vec2(e1[k], e2[k])).x;
  const glm::vec3 expected = glm::normalize(dpdu - n * glm::dot(n, dpdu));
  expect_vec_near(glm::vec3(t), expected, 1e-6f, "Gram-Schmidt of dP/du");
}

TEST(TriangleTangent, DegenerateUvsGiveNoFrame) {
  const glm::vec2 same[3] = {{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}};
  EXPECT_EQ(triangle_tangent(kCorners, same, kUp).w, 0.0f);
  const glm::vec2 line[3] = {{0, 0}, {1, 1}, {2, 2}};
  EXPECT_EQ(triangle_tangent(kCorners, line, kUp).w, 0.0f);
}

TEST(AnyTangent, IsUnitAndOrthogonal) {
  for (const glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0, -1, 0),
                            glm::normalize(glm::vec3(1, 2, -3)), glm::normalize(glm::vec3(-0.1f, 0.2f, 1e-7f))}) {
    const glm::vec3 t = any_tangent(n);
    EXPECT_NEAR(glm::length(t), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(t, n), 0.0f, 1e-6f);
  }
  EXPECT_NEAR(glm::dot(orthogonal_tangent(glm::vec3(0, 0, 1), kUp), kUp), 0.0f, 1e-6f) << "parallel input";
}

TEST(PerturbNormal, FlatTexelKeepsTheNormal) {
  // (128, 128, 255) is the usual flat texel; (2 * 128/255 - 1) is 1/255, not 0, so use
  // exact halves to check that nothing else moves the normal.
  EXPECT_EQ(perturb_normal(kUp, {1, 0, 0, 1}, {0.5f, 0.5f, 1.0f}, 1.0f), kUp);
  EXPECT_EQ(perturb_normal(kUp, {1, 0, 0, 1}, {0.5f, 0.5f, 0.5f}, 1.0f), kUp) << "zero vector: unchanged";
}

TEST(PerturbNormal, XFollowsTheTangentAndYTheBitangent) {
  const glm::vec4 right_handed(1, 0, 0, 1), left_handed(1, 0, 0, -1);
  expect_vec_near(perturb_normal(kUp, right_handed, {0.8f, 0.5f, 0.9f}, 1.0f), {0.6f, 0, 0.8f}, 1e-6f, "+X");
  expect_vec_near(perturb_normal(kUp, right_handed, {0.5f, 0.8f, 0.9f}, 1.0f), {0, 0.6f, 0.8f}, 1e-6f, "+Y, w = 1");
  expect_vec_near(perturb_normal(kUp, left_handed, {0.5f, 0.8f, 0.9f}, 1.0f), {0, -0.6f, 0.8f}, 1e-6f, "+Y, w = -1");
  expect_vec_near(perturb_normal(kUp, left_handed, {0.2f, 0.5f, 0.9f}, 1.0f), {-0.6f, 0, 0.8f}, 1e-6f, "-X");
}

TEST(PerturbNormal, ScaleAppliesToXYOnly) {
  const glm::vec3 n = perturb_normal(kUp, {1, 0, 0, 1}, {0.8f, 0.5f, 0.9f}, 0.5f);
  expect_vec_near(n, glm::normalize(glm::vec3(0.3f, 0, 0.8f)), 1e-6f, "scale 0.5");
  const glm::vec3 flat = perturb_normal(kUp, {1, 0, 0, 1}, {0.8f, 0.5f, 0.9f}, 0.0f);
  expect_vec_near(flat, kUp, 1e-6f, "scale 0");
}

TEST(FaceViewer, KeepsANormalThatFacesTheViewer) {
  const glm::vec3 ns = glm::normalize(glm::vec3(0.5f, 0, 1));
  const glm::vec3 wo = glm::normalize(glm::vec3(-0.2f, 0.1f, 1));
  EXPECT_EQ(face_viewer(ns, kUp, wo), ns);
}

TEST(FaceViewer, BendsANormalThatHidesTheViewer) {
  const glm::vec3 ns = glm::normalize(glm::vec3(1, 0.2f, 0.1f));   // leans far to +x
  const glm::vec3 wo = glm::normalize(glm::vec3(-1, 0, 0.15f));    // viewer low on the -x side
  ASSERT_LT(glm::dot(ns, wo), 0.0f);
  const glm::vec3 bent = face_viewer(ns, kUp, wo);
  EXPECT_NEAR(glm::length(bent), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(bent, wo), kMinShadingCosine, 1e-5f);
  EXPECT_GT(glm::dot(bent, kUp), 0.0f) << "still on the geometric side";
  EXPECT_NEAR(glm::dot(glm::cross(ns, wo), bent), 0.0f, 1e-5f) << "bent within the plane of ns and wo";
}

TEST(FaceViewer, UsesTheGeometricNormalWhenTheShadingNormalIsBelowTheSurface) {
  const glm::vec3 ns = glm::normalize(glm::vec3(0.3f, 0, -1));  // points into the surface
  const glm::vec3 wo = glm::normalize(glm::vec3(0.5f, 0, 1));
  const glm::vec3 bent = face_viewer(ns, kUp, wo);
  EXPECT_NEAR(glm::length(bent), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(bent, wo), kMinShadingCosine, 1e-5f);
  EXPECT_GT(glm::dot(bent, kUp), 0.0f);
  EXPECT_EQ(face_viewer(-kUp, kUp, kUp), kUp) << "viewer straight above";
}

}  // namespace
}  // namespace lancer
