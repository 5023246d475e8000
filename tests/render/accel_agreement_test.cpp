// Every accelerator gives the oracle's hits, so the images agree bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "accel/accel_factory.h"
#include "render/camera.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "simd/isa.h"
#include "test_paths.h"

namespace lancer {
namespace {

ImageRGB render_with(const Scene& scene, const std::string& accel, KdSplit split, IntegratorKind integrator,
                     Isa isa = best_supported_isa()) {
  KdBuildOptions kd;
  kd.split = split;
  const std::unique_ptr<Accelerator> a = make_accelerator(accel, scene.triangles, kd, isa);
  RenderSettings s;
  s.width = 48;
  s.height = 48;
  s.spp = 2;
  s.integrator = integrator;
  const PinholeCamera cam = PinholeCamera::from_desc(scene.cameras.at(0), s.width, s.height);
  RenderStats stats;
  return render_image(scene, *a, cam, s, stats);
}

TEST(AccelAgreement, KdTreeImagesEqualTheOraclesBitForBit) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  for (IntegratorKind integrator : {IntegratorKind::Whitted, IntegratorKind::PrimId}) {
    const ImageRGB oracle = render_with(scene, "brute", KdSplit::Sah, integrator);
    for (KdSplit split : {KdSplit::Sah, KdSplit::Middle, KdSplit::Median}) {
      const ImageRGB kd = render_with(scene, "kdtree", split, integrator);
      ASSERT_EQ(kd.rgb.size(), oracle.rgb.size());
      EXPECT_EQ(std::memcmp(kd.rgb.data(), oracle.rgb.data(), kd.rgb.size() * sizeof(float)), 0)
          << kd_split_name(split) << " " << integrator_name(integrator);
    }
  }
}

// Every ISA's kernels compute each lane exactly as the scalar oracle does.
TEST(AccelAgreement, EveryIsaRendersTheOraclesImage) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const ImageRGB oracle = render_with(scene, "brute", KdSplit::Sah, IntegratorKind::Whitted);
  for (Isa isa : supported_isas()) {
    const ImageRGB kd = render_with(scene, "kdtree", KdSplit::Sah, IntegratorKind::Whitted, isa);
    EXPECT_EQ(std::memcmp(kd.rgb.data(), oracle.rgb.data(), kd.rgb.size() * sizeof(float)), 0) << isa_name(isa);
  }
}

TEST(AccelFactory, NamesRoundTripAndUnknownNamesAreRefused) {
  for (auto name : kd_split_names()) {
    const auto split = parse_kd_split(name);
    ASSERT_TRUE(split.has_value());
    EXPECT_EQ(kd_split_name(*split), name);
  }
  EXPECT_FALSE(parse_kd_split("sweep").has_value());
  const TriangleSoA tris;
  EXPECT_THROW(make_accelerator("octree", tris), std::invalid_argument);
  EXPECT_EQ(accelerator_names().front(), "kdtree");
}

}  // namespace
}  // namespace lancer
