// The Cornell boxes: bit-identical across thread counts and tile sizes, seed-dependent,
// and free of NaN and infinity.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "simd/isa.h"
#include "test_paths.h"

namespace lancer {
namespace {

struct Cornell {
  Scene scene;
  explicit Cornell(const char* name) : scene(load_scene(test::scenes_dir() / name)) {}

  ImageRGB render(int threads, int tile_size, std::uint64_t seed, int size = 64, int spp = 4,
                  IntegratorKind integrator = IntegratorKind::Path, std::optional<Isa> vector_isa = {}) const {
    const BruteForce accel(scene.triangles);
    EXPECT_FALSE(scene.cameras.empty());
    const PinholeCamera cam = PinholeCamera::from_desc(scene.cameras.at(0), size, size);
    RenderSettings s;
    s.width = size;
    s.height = size;
    s.spp = spp;
    s.threads = threads;
    s.tile_size = tile_size;
    s.seed = seed;
    s.integrator = integrator;
    s.vector_isa = vector_isa;
    RenderStats stats;
    return render_image(scene, accel, cam, s, stats);
  }
};

bool bitwise_equal(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

class CornellScenes : public ::testing::TestWithParam<const char*> {
 protected:
  // The oracle is slow on the spheres' 1932 triangles: a smaller image for them.
  int size() const { return std::string(GetParam()).find("spheres") != std::string::npos ? 40 : 64; }
};

TEST_P(CornellScenes, BitIdenticalAcrossThreadsAndTiles) {
  const Cornell c(GetParam());
  const ImageRGB one = c.render(1, 16, 7, size());
  const ImageRGB two = c.render(2, 16, 7, size());
  const ImageRGB odd_tiles = c.render(2, 5, 7, size());
  // Tiles of 9 and 25 blocks: several wavefronts of four blocks per tile, the last partial.
  const ImageRGB wide_tiles = c.render(2, 24, 7, size());
  const ImageRGB whole_image = c.render(1, 64, 7, size());
  EXPECT_TRUE(bitwise_equal(one, two));
  EXPECT_TRUE(bitwise_equal(one, odd_tiles));
  EXPECT_TRUE(bitwise_equal(one, wide_tiles));
  EXPECT_TRUE(bitwise_equal(one, whole_image));
}

// The path tracer's vector passes over a bounce's paths (ray origins, the hits' geometry,
// the drawn sample values) give the image that scalar code gives, on every ISA this CPU
// runs; and so does the photon integrator, which shades its paths the same way.
TEST_P(CornellScenes, BitIdenticalAcrossTheVectorPassesIsas) {
  const Cornell c(GetParam());
  for (const IntegratorKind integrator : {IntegratorKind::Path, IntegratorKind::Photon}) {
    const ImageRGB scalar = c.render(2, 16, 5, 32, 2, integrator, Isa::Scalar);
    for (const Isa isa : supported_isas()) {
      if (isa == Isa::Scalar) continue;
      EXPECT_TRUE(bitwise_equal(scalar, c.render(2, 16, 5, 32, 2, integrator, isa)))
          << isa_name(isa) << ", " << integrator_name(integrator);
    }
  }
}

TEST_P(CornellScenes, SeedChangesTheImage) {
  const Cornell c(GetParam());
  EXPECT_FALSE(bitwise_equal(c.render(2, 16, 1, 32, 2), c.render(2, 16, 2, 32, 2)));
}

TEST_P(CornellScenes, EveryPixelFiniteAndTheLightVisible) {
  const Cornell c(GetParam());
  // Whitted: a light seen directly is exactly its emission (the path tracer adds the light
  // that the light's own surface reflects).
  const ImageRGB img = c.render(2, 16, 3, size(), 4, IntegratorKind::Whitted);
  double sum = 0.0;
  float max_red = 0.0f;
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    ASSERT_TRUE(std::isfinite(img.rgb[i])) << "value " << i;
    ASSERT_GE(img.rgb[i], 0.0f) << "value " << i;
    sum += img.rgb[i];
    if (i % 3 == 0) max_red = std::max(max_red, img.rgb[i]);
  }
  EXPECT_GT(sum / img.rgb.size(), 0.05);  // the box is lit
  // Pixels wholly inside the ceiling light show its emission, emissive factor (1, ...)
  // times strength 17: the light faces down into the box.
  EXPECT_NEAR(max_red, 17.0f, 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(Files, CornellScenes, ::testing::Values("cornell-box.gltf", "cornell-box-spheres.gltf"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param).find("spheres") != std::string::npos ? "Spheres" : "Box";
                         });

}  // namespace
}  // namespace lancer
