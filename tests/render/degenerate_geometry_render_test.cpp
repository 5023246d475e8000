// Duplicate triangles and subnormal positions through the whole renderer (issue 7): readers
// keep both (a duplicate is a valid triangle, a subnormal a finite coordinate), so the
// kd-tree, the ray offsets and the path tracer must take them without NaN, acne or a
// changed picture. The Cornell box is the scene: its corner is the origin, so many of its
// coordinates are exactly 0 and can be replaced by subnormals.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/camera.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "scene/scene_builder.h"
#include "image_estimate.h"
#include "test_paths.h"

namespace lancer {
namespace {

const Scene& cornell() {
  static const Scene scene = load_scene(test::scenes_dir() / "cornell-box.gltf");
  return scene;
}

// The scene's materials, cameras and lights, without triangles.
Scene empty_copy(const Scene& in) {
  Scene out;
  out.materials = in.materials;
  out.cameras = in.cameras;
  out.lights = in.lights;
  return out;
}

bool emissive(const Scene& s, std::size_t i) { return s.materials[s.material_id[i]].emission() != glm::vec3(0.0f); }

// Adds triangle i of s with corner k at position p[k], its corner attributes taken from
// corner first + k (mod 3): first = 1 for the corners in the other cyclic order.
void add(SceneBuilder& b, const Scene& s, std::size_t i, const glm::vec3 (&p)[3], int first = 0) {
  ASSERT_EQ(s.attrib_flags[i] & ~std::uint8_t(kHasNormals), 0) << "the Cornell box has normals only";
  glm::vec3 n[3];
  for (int k = 0; k < 3; ++k) n[k] = s.normals[3 * i + std::size_t((first + k) % 3)];
  CornerAttributes corners;
  if (s.attrib_flags[i] & kHasNormals) corners.normals = n;
  EXPECT_TRUE(b.add_triangle(p, s.material_id[i], std::uint32_t(i), corners));
}

// Every surface that does not emit twice: first with its corners in the other cyclic order
// (other edge functions, u and v, and t possibly a last bit apart), then as given. Both
// copies give a hit at the same place, and a ray leaving one must not hit the other.
Scene with_duplicates(const Scene& in) {
  Scene out = empty_copy(in);
  SceneBuilder b(out, "duplicates");
  for (std::size_t i = 0; i < in.triangle_count(); ++i) {
    const glm::vec3 p[3] = {in.triangles.vertex(i, 0), in.triangles.vertex(i, 1), in.triangles.vertex(i, 2)};
    if (!emissive(in, i)) add(b, in, i, {p[1], p[2], p[0]}, 1);
    add(b, in, i, p);
  }
  b.finish();
  return out;
}

// Every coordinate that is exactly 0 (the box's corner is the origin) becomes a subnormal
// of either sign, and triangles of subnormal size sit in that corner.
Scene with_subnormals(const Scene& in) {
  const float sub[] = {1e-40f, -3e-42f, std::numeric_limits<float>::denorm_min(), -1e-39f};
  Scene out = empty_copy(in);
  SceneBuilder b(out, "subnormals");
  int next = 0;
  for (std::size_t i = 0; i < in.triangle_count(); ++i) {
    glm::vec3 p[3] = {in.triangles.vertex(i, 0), in.triangles.vertex(i, 1), in.triangles.vertex(i, 2)};
    for (glm::vec3& v : p)
      for (int axis = 0; axis < 3; ++axis)
        if (v[axis] == 0.0f) v[axis] = sub[next++ % 4];
    add(b, in, i, p);
  }
  for (float s : sub) {
    const float a = std::fabs(s);
    const glm::vec3 tiny[3] = {{a, a, a}, {2.0f * a, a, a}, {a, 3.0f * a, 2.0f * a}};
    b.add_triangle(tiny, 0, 1000);  // may be dropped as zero area in double: either is right
  }
  b.finish();
  EXPECT_GT(next, 20);
  return out;
}

constexpr int kSize = 48;
constexpr int kBlock = 8;

ImageRGB render(const Scene& scene, int spp) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = s.height = kSize;
  s.spp = spp;
  s.integrator = IntegratorKind::Path;
  s.max_depth = 6;
  s.seed = 9;
  RenderStats stats;
  return render_image(scene, kd, PinholeCamera::from_desc(scene.cameras.at(0), kSize, kSize), s, stats);
}

std::size_t non_finite(const ImageRGB& image) {
  return std::size_t(std::count_if(image.rgb.begin(), image.rgb.end(), [](float v) { return !std::isfinite(v); }));
}

// The same seed makes both renders follow the same paths wherever the geometry answers the
// same, so the blocks agree far more closely than noise allows (offset_reference_test
// measures acne at 7 % of a block at this size and sample count).
constexpr double kTolerance = 0.015;

TEST(DegenerateGeometryRender, DuplicateTrianglesChangeNothing) {
  const Scene dup = with_duplicates(cornell());
  ASSERT_EQ(dup.triangle_count(), 2 * cornell().triangle_count() - 2);
  const ImageRGB reference = render(cornell(), 32), image = render(dup, 32);
  EXPECT_EQ(non_finite(image), 0u);
  const double worst = test::largest_block_difference(image, reference, kBlock);
  std::printf("[ info     ] largest block difference with duplicates: %.5f\n", worst);
  EXPECT_LT(worst, kTolerance);
}

TEST(DegenerateGeometryRender, SubnormalPositionsChangeNothing) {
  const Scene sub = with_subnormals(cornell());
  const ImageRGB reference = render(cornell(), 32), image = render(sub, 32);
  EXPECT_EQ(non_finite(image), 0u);
  const double worst = test::largest_block_difference(image, reference, kBlock);
  std::printf("[ info     ] largest block difference with subnormal positions: %.5f\n", worst);
  EXPECT_LT(worst, kTolerance);
}

}  // namespace
}  // namespace lancer
