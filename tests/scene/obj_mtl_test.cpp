// MTL materials on OBJ faces: the Phong-to-metallic-roughness mapping, textures, default
// materials, and missing or broken material and texture files.
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "scene/obj_reader.h"
#include "scene/obj_test_files.h"
#include "scene/scene_error.h"
#include "test_paths.h"

namespace lancer {
namespace {

using ObjMtl = test::ObjFilesTest;

const std::string kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

// One triangle per material name, in order, with texcoords.
std::string obj_using(const std::string& mtllib, const std::vector<std::string>& materials) {
  std::string text = "mtllib " + mtllib + "\n" + kQuad;
  for (const std::string& name : materials) text += "usemtl " + name + "\nf 1/1 2/2 3/3\n";
  return text;
}

const Material& material_of(const Scene& scene, std::size_t triangle) {
  return scene.materials.at(scene.material_id.at(triangle));
}

// A binary PPM (which stb_image reads) of width x 1 pixels with the given RGB bytes.
std::string ppm(const std::vector<std::uint8_t>& rgb) {
  std::string data = "P6\n" + std::to_string(rgb.size() / 3) + " 1\n255\n";
  data.append(rgb.begin(), rgb.end());
  return data;
}

TEST_F(ObjMtl, PhongParametersMapOntoMetallicRoughness) {
  write("m.mtl",
        "newmtl plastic\nKd 0.5 0.25 0.125\nKs 0.2 0.2 0.2\nNs 98\nillum 2\n"
        "newmtl matte\nKd 0.8 0.7 0.6\nKs 0 0 0\nillum 1\n"
        "newmtl gold\nKd 0.05 0.05 0.05\nKs 1 0.8 0.3\nNs 200\nillum 2\n"
        "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nNs 10\nillum 3\n"
        "newmtl glass\nKd 0 0 0\nKs 1 1 1\nTf 0.9 1 0.9\nNi 1.33\nd 0.5\nNs 1000\nillum 7\n"
        "newmtl lamp\nKd 1 1 1\nKe 10 5 0\n"
        "newmtl dim\nKd 1 1 1\nKe 0.5 0.25 0\n"
        "newmtl veil\nKd 1 1 1\nd 0.25\nNi 1.0\nillum 2\n"
        "newmtl tr\nKd 1 1 1\nTr 0.75\nNi 1.7\n");
  const std::vector<std::string> names = {"plastic", "matte", "gold", "mirror", "glass", "lamp", "dim", "veil", "tr"};
  const Scene scene = read_obj(write("m.obj", obj_using("m.mtl", names)));
  ASSERT_EQ(scene.triangle_count(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(material_of(scene, i).name, names[i]);
  EXPECT_EQ(scene.materials.size(), names.size()) << "no default material: every face has one";

  const Material& plastic = material_of(scene, 0);
  EXPECT_EQ(plastic.base_color, glm::vec4(0.5f, 0.25f, 0.125f, 1.0f));
  EXPECT_EQ(plastic.metallic, 0.0f);
  EXPECT_NEAR(plastic.roughness, 0.37606031f, 1e-6f);  // (2 / (98 + 2))^(1/4)
  EXPECT_EQ(plastic.specular, 1.0f);
  EXPECT_EQ(plastic.alpha_mode, AlphaMode::Opaque);
  EXPECT_EQ(plastic.transmission, 0.0f);
  EXPECT_EQ(plastic.ior, 1.5f) << "no Ni: glTF's default";

  const Material& matte = material_of(scene, 1);
  EXPECT_EQ(matte.base_color, glm::vec4(0.8f, 0.7f, 0.6f, 1.0f));
  EXPECT_EQ(matte.specular, 0.0f) << "Ks 0 and illum 1: no specular lobe";
  EXPECT_NEAR(matte.roughness, 0.90360200f, 1e-6f) << "Ns absent reads as 1";

  const Material& gold = material_of(scene, 2);
  EXPECT_EQ(gold.metallic, 1.0f) << "strong Ks over a dark Kd";
  EXPECT_EQ(gold.base_color, glm::vec4(1.0f, 0.8f, 0.3f, 1.0f));
  EXPECT_NEAR(gold.roughness, 0.31544210f, 1e-6f);

  const Material& mirror = material_of(scene, 3);
  EXPECT_EQ(mirror.metallic, 1.0f);
  EXPECT_EQ(mirror.roughness, 0.0f);
  EXPECT_EQ(mirror.base_color, glm::vec4(0.9f, 0.9f, 0.9f, 1.0f));

  const Material& glass = material_of(scene, 4);
  EXPECT_EQ(glass.transmission, 1.0f);
  EXPECT_GT(glass.thickness, 0.0f) << "illum 7 refracts: a volume, not a thin wall";
  EXPECT_EQ(glass.metallic, 0.0f);
  EXPECT_FLOAT_EQ(glass.ior, 1.33f);
  EXPECT_EQ(glass.base_color, glm::vec4(0.9f, 1.0f, 0.9f, 1.0f)) << "Tf tints the glass; d is not alpha";
  EXPECT_EQ(glass.alpha_mode, AlphaMode::Opaque);
  EXPECT_NEAR(glass.roughness, 0.21136865f, 1e-6f);

  const Material& lamp = material_of(scene, 5);
  EXPECT_EQ(lamp.emission(), glm::vec3(10.0f, 5.0f, 0.0f));
  EXPECT_EQ(lamp.emissive_factor, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(lamp.emissive_strength, 10.0f);
  const Material& dim = material_of(scene, 6);
  EXPECT_EQ(dim.emissive_factor, glm::vec3(0.5f, 0.25f, 0.0f));
  EXPECT_EQ(dim.emissive_strength, 1.0f);
  EXPECT_FALSE(plastic.emissive());

  const Material& veil = material_of(scene, 7);
  EXPECT_EQ(veil.base_color.a, 0.25f);
  EXPECT_EQ(veil.alpha_mode, AlphaMode::Blend);
  EXPECT_EQ(veil.ior, 1.5f) << "Ni 1.0 keeps the default";
  const Material& tr = material_of(scene, 8);
  EXPECT_EQ(tr.base_color.a, 0.25f) << "Tr 0.75 is d 0.25";
  EXPECT_EQ(tr.alpha_mode, AlphaMode::Blend);
  EXPECT_FLOAT_EQ(tr.ior, 1.7f);
}

TEST_F(ObjMtl, FacesWithoutMaterialGetAnExplicitDefault) {
  write("m.mtl", "newmtl red\nKd 1 0 0\n");
  const Scene scene =
      read_obj(write("m.obj", "mtllib m.mtl\n" + kQuad + "f 1 2 3\nusemtl red\nf 1 3 4\nusemtl nosuch\nf 2 3 4\n"));
  ASSERT_EQ(scene.triangle_count(), 3u);
  ASSERT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(material_of(scene, 0).name, "default");
  EXPECT_EQ(material_of(scene, 1).name, "red");
  EXPECT_EQ(material_of(scene, 2).name, "default") << "an unknown usemtl name";
  EXPECT_EQ(material_of(scene, 0).base_color, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
  EXPECT_EQ(material_of(scene, 0).metallic, 0.0f);
}

TEST_F(ObjMtl, MissingMtlWarnsAndUsesTheDefaultMaterial) {
  testing::internal::CaptureStderr();
  const Scene scene = read_obj(write("m.obj", obj_using("absent.mtl", {"red"})));
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(scene.triangle_count(), 1u);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "default");
  EXPECT_NE(err.find("warning"), std::string::npos) << err;
  EXPECT_NE(err.find("absent.mtl"), std::string::npos) << err;
  EXPECT_NE(err.find("m.obj"), std::string::npos) << err;
}

TEST_F(ObjMtl, TexturesAreLoadedOnceAndMapped) {
  write("tex/albedo.ppm", ppm({255, 0, 0, 0, 255, 0}));
  write("tex/normal.ppm", ppm({128, 128, 255}));
  write("tex/glow.ppm", ppm({10, 20, 30}));
  write("lib/m.mtl",
        "newmtl a\nKd 1 1 1\nmap_Kd ../tex/albedo.ppm\nmap_Bump -bm 0.5 ../tex/normal.ppm\n"
        "newmtl b\nKd 1 1 1\nmap_Kd -clamp on ../tex/albedo.ppm\nnorm ../tex/normal.ppm\nmap_Ke ../tex/glow.ppm\n"
        "newmtl c\nmap_Kd ../tex/albedo.ppm\n");
  const Scene scene = read_obj(write("m.obj", obj_using("lib/m.mtl", {"a", "b", "c"})));
  ASSERT_EQ(scene.triangle_count(), 3u);
  ASSERT_EQ(scene.images.size(), 3u) << "albedo.ppm is shared";
  const Material& a = material_of(scene, 0);
  const Material& b = material_of(scene, 1);
  const Material& c = material_of(scene, 2);
  ASSERT_TRUE(a.base_color_texture.present());
  const Image& albedo = scene.images.at(scene.textures.at(a.base_color_texture.texture).image);
  EXPECT_EQ(albedo.width, 2);
  EXPECT_EQ(albedo.height, 1);
  EXPECT_EQ(albedo.channels, 3);
  EXPECT_EQ(albedo.pixels, (std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0}));
  EXPECT_EQ(scene.textures.at(a.base_color_texture.texture).wrap_s, 10497);
  ASSERT_TRUE(a.normal_texture.present());
  EXPECT_EQ(a.normal_texture.scale, 0.5f);
  EXPECT_FALSE(a.emissive_texture.present());

  ASSERT_TRUE(b.base_color_texture.present());
  EXPECT_NE(b.base_color_texture.texture, a.base_color_texture.texture) << "-clamp needs its own sampler";
  EXPECT_EQ(scene.textures.at(b.base_color_texture.texture).image, scene.textures.at(a.base_color_texture.texture).image);
  EXPECT_EQ(scene.textures.at(b.base_color_texture.texture).wrap_t, 33071);
  EXPECT_EQ(b.normal_texture.texture, a.normal_texture.texture);
  EXPECT_EQ(b.normal_texture.scale, 1.0f);
  ASSERT_TRUE(b.emissive_texture.present());
  EXPECT_EQ(b.emissive_factor, glm::vec3(1.0f)) << "map_Ke without Ke";
  EXPECT_EQ(scene.images.at(scene.textures.at(b.emissive_texture.texture).image).pixels,
            (std::vector<std::uint8_t>{10, 20, 30}));
  EXPECT_EQ(c.base_color_texture.texture, a.base_color_texture.texture);
  EXPECT_EQ(c.base_color, glm::vec4(1.0f)) << "map_Kd without Kd";
}

TEST_F(ObjMtl, MissingOrCorruptTexturesAreErrorsNamingTextureAndObj) {
  write("missing.mtl", "newmtl a\nmap_Kd nothere.png\n");
  write("corrupt.mtl", "newmtl a\nmap_Kd broken.png\n");
  write("broken.png", "\x89PNG\r\n\x1a\n this is not really a png");
  write("badnormal.mtl", "newmtl a\nbump gone.png\n");
  for (const std::string mtl : {"missing", "corrupt", "badnormal"}) {
    const auto path = write(mtl + ".obj", obj_using(mtl + ".mtl", {"a"}));
    try {
      read_obj(path);
      ADD_FAILURE() << "no SceneError for " << mtl;
    } catch (const SceneError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      const std::string texture = mtl == "missing" ? "nothere.png" : mtl == "corrupt" ? "broken.png" : "gone.png";
      EXPECT_NE(message.find("texture '" + texture + "'"), std::string::npos) << message;
    }
  }
}

TEST_F(ObjMtl, NonFiniteMaterialValuesAreErrors) {
  write("m.mtl", "newmtl hot\nKe 1e999 0 0\n");
  const auto path = write("m.obj", obj_using("m.mtl", {"hot"}));
  EXPECT_THROW(read_obj(path), SceneError);
}

TEST_F(ObjMtl, SpotModelWithItsTexture) {
  const auto models = test::models_dir();
  if (!std::filesystem::exists(models / "spot.obj") || !std::filesystem::exists(models / "spot_texture.png"))
    GTEST_SKIP() << "spot.obj / spot_texture.png not found in " << models;
  // spot.obj names no MTL; read it as shipped, then through a copy that uses the texture.
  const Scene plain = read_obj(models / "spot.obj");
  EXPECT_EQ(plain.triangle_count() + plain.stats.degenerate_dropped, 5856u);
  for (std::uint8_t flags : plain.attrib_flags) ASSERT_EQ(flags, kHasTexcoords);

  write("spot.mtl", "newmtl spot\nKd 1 1 1\nmap_Kd " + (models / "spot_texture.png").string() + "\n");
  std::ifstream in(models / "spot.obj", std::ios::binary);
  const std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Scene scene = read_obj(write("spot.obj", "mtllib spot.mtl\nusemtl spot\n" + body));
  EXPECT_EQ(scene.triangle_count(), plain.triangle_count());
  ASSERT_EQ(scene.materials.size(), 1u);
  ASSERT_TRUE(scene.materials[0].base_color_texture.present());
  const Image& image = scene.images.at(scene.textures.at(scene.materials[0].base_color_texture.texture).image);
  EXPECT_GT(image.width, 0);
  EXPECT_GT(image.height, 0);
  EXPECT_EQ(image.pixels.size(), static_cast<std::size_t>(image.width) * image.height * image.channels);
  // spot's vt lie in u [-0.0523, 0.9891], v [0.1112, 1.0007]; Scene flips v to 1 - v.
  glm::vec2 lo(1e9f), hi(-1e9f);
  for (const glm::vec2& uv : scene.texcoords) {
    lo = glm::min(lo, uv);
    hi = glm::max(hi, uv);
  }
  EXPECT_NEAR(lo.x, -0.0522421f, 1e-6f);
  EXPECT_NEAR(hi.x, 0.989055f, 1e-6f);
  EXPECT_NEAR(lo.y, 1.0f - 1.00065f, 1e-6f);
  EXPECT_NEAR(hi.y, 1.0f - 0.111175f, 1e-6f);
}

}  // namespace
}  // namespace lancer
