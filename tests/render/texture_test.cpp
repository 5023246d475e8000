// Texture lookups: UV convention, wrap modes, nearest and bilinear filtering, sRGB
// decoding, channel expansion and KHR_texture_transform, on small images built here.
#include "render/texture.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "scene/gltf_texture_refs.h"

namespace lancer {
namespace {

// A width x height single-channel image whose texel (x, y) holds code(x, y).
template <typename Code>
Image grey_image(int width, int height, Code code) {
  Image image;
  image.name = "test";
  image.width = width;
  image.height = height;
  image.channels = 1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.pixels.push_back(std::uint8_t(code(x, y)));
  return image;
}

// 4 x 2 texels, code 10 + x + 4 y * 10 - every texel different.
Image ramp() { return grey_image(4, 2, [](int x, int y) { return 10 + 10 * x + 40 * y; }); }

Texture sampler(int wrap_s, int wrap_t, int mag = kFilterNearest) {
  Texture t;
  t.image = 0;
  t.wrap_s = wrap_s;
  t.wrap_t = wrap_t;
  t.mag_filter = mag;
  return t;
}

float code(int c) { return float(c) / 255.0f; }

// IEC 61966-2-1 decoding of 8-bit code c, in double.
double srgb_formula(int c) {
  const double e = c / 255.0;
  return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

float nearest(const Image& image, const Texture& texture, glm::vec2 uv) {
  return sample_image(image, texture, uv, TexelEncoding::Linear, TexelFilter::Nearest).r;
}
float linear(const Image& image, const Texture& texture, glm::vec2 uv) {
  return sample_image(image, texture, uv, TexelEncoding::Linear, TexelFilter::Linear).r;
}

TEST(Texture, UvOriginIsTheTopLeftTexel) {
  const Image image = ramp();
  const Texture t = sampler(kWrapRepeat, kWrapRepeat);
  EXPECT_EQ(nearest(image, t, {0.01f, 0.01f}), code(10)) << "top-left";
  EXPECT_EQ(nearest(image, t, {0.99f, 0.01f}), code(40)) << "top-right";
  EXPECT_EQ(nearest(image, t, {0.01f, 0.99f}), code(50)) << "bottom-left";
  EXPECT_EQ(nearest(image, t, {0.99f, 0.99f}), code(80)) << "bottom-right";
}

TEST(Texture, NearestReadsTheTexelWhoseSquareHoldsTheUv) {
  const Image image = ramp();
  const Texture t = sampler(kWrapRepeat, kWrapRepeat);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const float expected = code(10 + 10 * x + 40 * y);
      // Centre and just inside both edges of texel (x, y).
      EXPECT_EQ(nearest(image, t, {(x + 0.5f) / 4, (y + 0.5f) / 2}), expected) << x << "," << y;
      EXPECT_EQ(nearest(image, t, {(x + 0.01f) / 4, (y + 0.99f) / 2}), expected) << x << "," << y;
      EXPECT_EQ(nearest(image, t, {(x + 0.99f) / 4, (y + 0.01f) / 2}), expected) << x << "," << y;
    }
  // The left edge of texel 2 belongs to texel 2.
  EXPECT_EQ(nearest(image, t, {0.5f, 0.25f}), code(30));
}

TEST(Texture, BilinearIsExactAtTexelCentresAndBlendsBetweenThem) {
  const Image image = ramp();
  const Texture t = sampler(kWrapClampToEdge, kWrapClampToEdge, kFilterLinear);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      EXPECT_EQ(linear(image, t, {(x + 0.5f) / 4, (y + 0.5f) / 2}), code(10 + 10 * x + 40 * y)) << x << "," << y;
  // Halfway between the centres of texels 1 and 2 of the top row: u = 0.5.
  EXPECT_FLOAT_EQ(linear(image, t, {0.5f, 0.25f}), 0.5f * (code(20) + code(30)));
  // A quarter of the way from texel 0's centre to texel 1's.
  EXPECT_FLOAT_EQ(linear(image, t, {0.1875f, 0.25f}), 0.75f * code(10) + 0.25f * code(20));
  // The centre of the four top-left texels: all four weigh 1/4.
  EXPECT_FLOAT_EQ(linear(image, t, {0.25f, 0.5f}), 0.25f * (code(10) + code(20) + code(50) + code(60)));
}

TEST(Texture, NearestAndLinearDifferOffCentre) {
  const Image image = ramp();
  const glm::vec2 uv{0.425f, 0.25f};  // in texel 1, 0.2 texels right of its centre
  EXPECT_EQ(nearest(image, sampler(kWrapRepeat, kWrapRepeat), uv), code(20));
  EXPECT_NEAR(linear(image, sampler(kWrapRepeat, kWrapRepeat, kFilterLinear), uv), 0.8f * code(20) + 0.2f * code(30),
              1e-6f);
}

TEST(Texture, RepeatWrapsWholePeriods) {
  const Image image = ramp();
  const Texture t = sampler(kWrapRepeat, kWrapRepeat);
  for (float shift : {-3.0f, -1.0f, 1.0f, 2.0f, 1000.0f}) {
    EXPECT_EQ(nearest(image, t, {0.375f + shift, 0.25f}), code(20)) << shift;
    EXPECT_EQ(nearest(image, t, {0.375f, 0.75f + shift}), code(60)) << shift;
  }
  EXPECT_EQ(nearest(image, t, {-0.125f, 0.25f}), code(40)) << "just left of 0 is the last column";
  EXPECT_EQ(nearest(image, t, {1.0f, 0.25f}), code(10)) << "u = 1 is u = 0";
  // Linear at the left edge blends the last and first columns.
  EXPECT_FLOAT_EQ(linear(image, sampler(kWrapRepeat, kWrapClampToEdge, kFilterLinear), {0.0f, 0.25f}),
                  0.5f * (code(10) + code(40)));
}

TEST(Texture, ClampToEdgeHoldsTheBorderTexels) {
  const Image image = ramp();
  const Texture t = sampler(kWrapClampToEdge, kWrapClampToEdge);
  EXPECT_EQ(nearest(image, t, {-0.5f, 0.25f}), code(10));
  EXPECT_EQ(nearest(image, t, {-1e9f, 0.25f}), code(10));
  EXPECT_EQ(nearest(image, t, {1.0f, 0.25f}), code(40));
  EXPECT_EQ(nearest(image, t, {7.5f, 0.25f}), code(40));
  EXPECT_EQ(nearest(image, t, {0.375f, 3.0f}), code(60));
  EXPECT_EQ(nearest(image, t, {0.375f, -3.0f}), code(20));
  const Texture l = sampler(kWrapClampToEdge, kWrapClampToEdge, kFilterLinear);
  EXPECT_EQ(linear(image, l, {0.0f, 0.25f}), code(10)) << "no blending with the far edge";
  EXPECT_EQ(linear(image, l, {1.0f, 0.25f}), code(40));
  EXPECT_EQ(linear(image, l, {0.0f, 0.0f}), code(10));
  EXPECT_EQ(linear(image, l, {1.0f, 1.0f}), code(80));
}

TEST(Texture, MirroredRepeatReflectsEveryOtherPeriod) {
  const Image image = ramp();
  const Texture t = sampler(kWrapMirroredRepeat, kWrapMirroredRepeat);
  // Texel columns along u: [0,1) 0 1 2 3, [1,2) 3 2 1 0, [2,3) 0 1 2 3, [-1,0) 3 2 1 0.
  const int expected_column[] = {0, 1, 2, 3, 3, 2, 1, 0, 0, 1, 2, 3};
  for (int k = 0; k < 12; ++k) {
    const float u = (k + 0.5f) / 4;
    EXPECT_EQ(nearest(image, t, {u, 0.25f}), code(10 + 10 * expected_column[k])) << "u " << u;
  }
  for (int k = 1; k <= 8; ++k) {
    const float u = -(k - 0.5f) / 4;  // -0.125, -0.375, ...
    const int column = k <= 4 ? k - 1 : 8 - k;
    EXPECT_EQ(nearest(image, t, {u, 0.25f}), code(10 + 10 * column)) << "u " << u;
  }
  EXPECT_EQ(nearest(image, t, {0.375f, 1.25f}), code(60)) << "v in [1, 2) reads rows bottom to top";
  EXPECT_EQ(nearest(image, t, {0.375f, 1.75f}), code(20));
  const Texture l = sampler(kWrapMirroredRepeat, kWrapMirroredRepeat, kFilterLinear);
  EXPECT_EQ(linear(image, l, {0.0f, 0.25f}), code(10)) << "the mirror image of texel 0 is texel 0";
  EXPECT_EQ(linear(image, l, {1.0f, 0.25f}), code(40));
  EXPECT_EQ(linear(image, l, {2.0f, 0.25f}), code(10));
}

TEST(Texture, WrapModesArePerAxis) {
  const Image image = ramp();
  const Texture t = sampler(kWrapRepeat, kWrapClampToEdge);
  EXPECT_EQ(nearest(image, t, {1.375f, 5.0f}), code(60)) << "u repeats, v clamps to the bottom row";
  const Texture m = sampler(kWrapClampToEdge, kWrapMirroredRepeat);
  EXPECT_EQ(nearest(image, m, {-2.0f, 1.25f}), code(50)) << "u clamps to column 0, v mirrors to row 1";
}

TEST(Texture, NonFiniteCoordinatesReadTheOriginTexel) {
  const Image image = ramp();
  for (int wrap : {kWrapRepeat, kWrapClampToEdge, kWrapMirroredRepeat}) {
    const Texture t = sampler(wrap, wrap);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(nearest(image, t, {nan, nan}), code(10)) << wrap;
    EXPECT_EQ(nearest(image, t, {inf, -inf}), code(10)) << wrap;
  }
}

TEST(Texture, FilterChoiceFollowsTheSampler) {
  Texture t;
  EXPECT_EQ(texel_filter(t), TexelFilter::Linear) << "absent magFilter";
  EXPECT_EQ(texel_filter(t, true), TexelFilter::Linear) << "absent minFilter";
  t.mag_filter = kFilterNearest;
  EXPECT_EQ(texel_filter(t), TexelFilter::Nearest);
  t.mag_filter = kFilterLinear;
  EXPECT_EQ(texel_filter(t), TexelFilter::Linear);
  const std::pair<int, TexelFilter> min_cases[] = {{9728, TexelFilter::Nearest}, {9729, TexelFilter::Linear},
                                                   {9984, TexelFilter::Nearest}, {9985, TexelFilter::Linear},
                                                   {9986, TexelFilter::Nearest}, {9987, TexelFilter::Linear}};
  for (const auto& [filter, expected] : min_cases) {
    t.min_filter = filter;
    EXPECT_EQ(texel_filter(t, true), expected) << filter;
    EXPECT_EQ(texel_filter(t, false), TexelFilter::Linear) << "magnification ignores minFilter";
  }
}

TEST(Texture, SrgbDecodeMatchesTheIecFormulaForEveryCode) {
  const Image image = grey_image(256, 1, [](int x, int) { return x; });
  const Texture t = sampler(kWrapClampToEdge, kWrapClampToEdge);
  for (int c = 0; c < 256; ++c) {
    const glm::vec2 uv{(c + 0.5f) / 256, 0.5f};
    const double expected = srgb_formula(c);
    const glm::vec4 s = sample_image(image, t, uv, TexelEncoding::Srgb, TexelFilter::Nearest);
    EXPECT_NEAR(s.r, expected, 1e-7 + 1e-6 * expected) << c;
    EXPECT_EQ(s.g, s.r);
    EXPECT_EQ(s.b, s.r);
    EXPECT_EQ(s.a, 1.0f);
    EXPECT_EQ(sample_image(image, t, uv, TexelEncoding::Linear, TexelFilter::Nearest).r, float(c) / 255.0f) << c;
  }
}

TEST(Texture, SrgbTexelsAreDecodedBeforeTheyAreFiltered) {
  const Image image = grey_image(2, 1, [](int x, int) { return x == 0 ? 0 : 255; });
  const Texture t = sampler(kWrapClampToEdge, kWrapClampToEdge, kFilterLinear);
  const glm::vec4 mid = sample_image(image, t, {0.5f, 0.5f}, TexelEncoding::Srgb, TexelFilter::Linear);
  EXPECT_FLOAT_EQ(mid.r, 0.5f) << "linear 0 and 1 average to 0.5, not to the decode of code 127.5";
}

TEST(Texture, ChannelsExpandAndAlphaStaysLinear) {
  Image ga;  // grey + alpha
  ga.width = ga.height = 1;
  ga.channels = 2;
  ga.pixels = {188, 51};
  const Texture t = sampler(kWrapRepeat, kWrapRepeat);
  const glm::vec4 s = sample_image(ga, t, {0.5f, 0.5f}, TexelEncoding::Srgb, TexelFilter::Nearest);
  EXPECT_NEAR(s.r, srgb_formula(188), 1e-6);
  EXPECT_EQ(s.g, s.r);
  EXPECT_EQ(s.b, s.r);
  EXPECT_EQ(s.a, 51.0f / 255.0f) << "alpha is never sRGB";

  Image rgba = ga;
  rgba.channels = 4;
  rgba.pixels = {255, 0, 128, 64};
  const glm::vec4 c = sample_image(rgba, t, {0.5f, 0.5f}, TexelEncoding::Linear, TexelFilter::Nearest);
  EXPECT_EQ(c, glm::vec4(1.0f, 0.0f, 128.0f / 255.0f, 64.0f / 255.0f));
  rgba.channels = 3;
  rgba.pixels = {255, 0, 128};
  EXPECT_EQ(sample_image(rgba, t, {0.5f, 0.5f}, TexelEncoding::Linear, TexelFilter::Nearest),
            glm::vec4(1.0f, 0.0f, 128.0f / 255.0f, 1.0f));
}

// A 4 x 4 image whose texel (x, y) holds 16 y + x, and a scene holding it as texture 0.
Scene grid_scene(int wrap = kWrapRepeat) {
  Scene scene;
  scene.images.push_back(grey_image(4, 4, [](int x, int y) { return 16 * y + x; }));
  scene.textures.push_back(sampler(wrap, wrap));
  return scene;
}

int texel_at(const Scene& scene, const TextureRef& ref, glm::vec2 uv0, glm::vec2 uv1 = glm::vec2(0.0f)) {
  return int(std::lround(sample_texture(scene, ref, uv0, uv1, TexelEncoding::Linear).r * 255.0f));
}

TEST(TextureTransform, OffsetAndScaleMoveTheLookup) {
  const Scene scene = grid_scene();
  TextureRef ref;
  ref.texture = 0;
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 0) << "identity";
  ref.transform = gltf::texture_transform_matrix({0.25f, 0.5f}, 0.0f, {1.0f, 1.0f});
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 16 * 2 + 1);
  ref.transform = gltf::texture_transform_matrix({0.0f, 0.0f}, 0.0f, {2.0f, 3.0f});
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 16 * 1 + 1) << "(0.25, 0.375)";
  // Scale applies before the offset: (0.125 * 2 + 0.25, 0.125 * 2 + 0) = (0.5, 0.25).
  ref.transform = gltf::texture_transform_matrix({0.25f, 0.0f}, 0.0f, {2.0f, 2.0f});
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 16 * 1 + 2);
}

TEST(TextureTransform, RotationFollowsTheExtensionsExample) {
  // KHR_texture_transform's example: offset (0, 1), rotation pi/2, scale 0.5 shows the
  // lower-left quadrant of the image rotated clockwise by 90 degrees, i.e.
  // (u, v) -> (v / 2, 1 - u / 2).
  const glm::mat3 m = gltf::texture_transform_matrix({0.0f, 1.0f}, float(std::numbers::pi / 2), {0.5f, 0.5f});
  for (const glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(0.3f, 0.8f)}) {
    const glm::vec3 r = m * glm::vec3(uv, 1.0f);
    EXPECT_NEAR(r.x, 0.5f * uv.y, 1e-6f) << uv.x << "," << uv.y;
    EXPECT_NEAR(r.y, 1.0f - 0.5f * uv.x, 1e-6f) << uv.x << "," << uv.y;
  }
  Scene scene = grid_scene();
  TextureRef ref;
  ref.texture = 0;
  ref.transform = m;
  // The rotated quadrant's top-left is the image's bottom-left texel (0, 3), its
  // top-right the quadrant's top-left (0, 2), its bottom-left the quadrant's
  // bottom-right (1, 3).
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 16 * 3 + 0);
  EXPECT_EQ(texel_at(scene, ref, {0.875f, 0.125f}), 16 * 2 + 0);
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.875f}), 16 * 3 + 1);
  EXPECT_EQ(texel_at(scene, ref, {0.875f, 0.875f}), 16 * 2 + 1);
}

TEST(TextureTransform, FlippingTheTAxisGivesABottomLeftOrigin) {
  // The extension's second example: offset (0, 1), scale (1, -1).
  const Scene scene = grid_scene();
  TextureRef ref;
  ref.texture = 0;
  ref.transform = gltf::texture_transform_matrix({0.0f, 1.0f}, 0.0f, {1.0f, -1.0f});
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}), 16 * 3);
  EXPECT_EQ(texel_at(scene, ref, {0.875f, 0.875f}), 3);
}

TEST(TextureLookup, TexcoordSetSelectsTheUv) {
  const Scene scene = grid_scene();
  TextureRef ref;
  ref.texture = 0;
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}, {0.875f, 0.875f}), 0);
  ref.texcoord = 1;
  EXPECT_EQ(texel_at(scene, ref, {0.125f, 0.125f}, {0.875f, 0.875f}), 16 * 3 + 3);
}

TEST(TextureLookup, AbsentTextureOrImageIsNeutral) {
  Scene scene = grid_scene();
  EXPECT_EQ(texture_image(scene, TextureRef{}), nullptr);
  EXPECT_EQ(sample_texture(scene, TextureRef{}, {0.5f, 0.5f}, {0, 0}, TexelEncoding::Srgb), glm::vec4(1.0f));
  scene.textures[0].image = -1;  // e.g. a texture whose only source is an unsupported extension
  TextureRef ref;
  ref.texture = 0;
  EXPECT_EQ(texture_image(scene, ref), nullptr);
  EXPECT_EQ(sample_texture(scene, ref, {0.5f, 0.5f}, {0, 0}, TexelEncoding::Linear), glm::vec4(1.0f));
}

}  // namespace
}  // namespace lancer
