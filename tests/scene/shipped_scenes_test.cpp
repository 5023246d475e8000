// The scenes the project ships (scenes/, rendered for the README gallery): every one
// loads and has a light; the gallery's four have their camera; the textured still life
// carries base-colour, normal and metallic-roughness textures with UVs and tangents in
// glTF's convention; the depth-of-field Cornell box has a thin lens focused on its
// middle sphere.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> shipped_scene_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(test::scenes_dir())) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".gltf" || ext == ".glb" || ext == ".obj")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

const Material* material_named(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return &m;
  ADD_FAILURE() << s.source << ": no material named '" << name << "'";
  return nullptr;
}

std::uint32_t material_index(const Scene& s, const Material* m) { return std::uint32_t(m - s.materials.data()); }

const Image* image_of(const Scene& s, const TextureRef& ref) {
  if (!ref.present() || std::size_t(ref.texture) >= s.textures.size()) return nullptr;
  const int image = s.textures[std::size_t(ref.texture)].image;
  return image >= 0 && std::size_t(image) < s.images.size() ? &s.images[std::size_t(image)] : nullptr;
}

TEST(ShippedScenes, TheGalleryScenesAreAllFound) {
  std::set<std::string> names;
  for (const fs::path& f : shipped_scene_files()) names.insert(fs::relative(f, test::scenes_dir()).generic_string());
  for (const char* expected : {"cornell-box.gltf", "cornell-box-spheres.gltf", "cornell-box-dof.gltf",
                               "textured/still-life.gltf"})
    EXPECT_EQ(names.count(expected), 1u) << "scenes/" << expected << " is missing";
}

// The gallery renders each of its scenes through the scene's own camera.
TEST(ShippedScenes, GalleryScenesHaveTheirCamera) {
  for (const char* file : {"cornell-box.gltf", "cornell-box-spheres.gltf", "cornell-box-dof.gltf",
                           "textured/still-life.gltf"}) {
    SCOPED_TRACE(file);
    const Scene s = load_scene(test::scenes_dir() / file);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].aspect_ratio.value_or(0.0f), 1.0f) << "the gallery images are square";
  }
}

TEST(ShippedScenes, EveryOneLoadsWithALight) {
  for (const fs::path& file : shipped_scene_files()) {
    SCOPED_TRACE(file.string());
    const Scene s = load_scene(file);
    EXPECT_GT(s.triangle_count(), 0u);
    EXPECT_EQ(s.stats.degenerate_dropped, 0u);
    std::size_t emitting = 0;
    for (std::size_t t = 0; t < s.triangle_count(); ++t) emitting += s.materials[s.material_id[t]].emissive();
    EXPECT_TRUE(emitting > 0 || !s.lights.empty()) << "no emissive triangle and no punctual light";
  }
}

class StillLife : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { scene_ = new Scene(load_scene(test::scenes_dir() / "textured/still-life.gltf")); }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  static const Scene& scene() { return *scene_; }

 private:
  static Scene* scene_;
};

Scene* StillLife::scene_ = nullptr;

// Wall, floor and torus have all three textures; the sphere has normal and
// metallic-roughness only (its colour is the copper factor).
TEST_F(StillLife, TexturedMaterialsHaveTheirImagesDecoded) {
  for (const char* name : {"bricks", "floor_tiles", "glazed_torus", "hammered_copper"}) {
    SCOPED_TRACE(name);
    const Material* m = material_named(scene(), name);
    ASSERT_NE(m, nullptr);
    const bool has_colour = std::string(name) != "hammered_copper";
    EXPECT_EQ(m->base_color_texture.present(), has_colour);
    for (const TextureRef* ref : {&m->normal_texture, &m->metallic_roughness_texture}) {
      const Image* image = image_of(scene(), *ref);
      ASSERT_NE(image, nullptr);
      EXPECT_GE(image->width, 256);
      EXPECT_EQ(image->width, image->height);
      EXPECT_EQ(image->channels, 3);
    }
    if (has_colour) {
      EXPECT_NE(image_of(scene(), m->base_color_texture), nullptr);
    }
    EXPECT_FLOAT_EQ(m->normal_texture.scale, 1.0f);
  }
}

// Every texel of a normal map must decode to a unit vector leaning out of the surface
// (z > 0); an sRGB-encoded or channel-swapped map would fail this.
TEST_F(StillLife, NormalMapsDecodeToUnitOutwardVectors) {
  for (const char* name : {"bricks", "floor_tiles", "hammered_copper"}) {
    SCOPED_TRACE(name);
    const Image* image = image_of(scene(), material_named(scene(), name)->normal_texture);
    ASSERT_NE(image, nullptr);
    float min_z = 1.0f, worst_length_error = 0.0f, max_tilt_x = 0.0f, max_tilt_y = 0.0f;
    for (std::size_t i = 0; i + 2 < image->pixels.size(); i += 3) {
      const glm::vec3 n = glm::vec3(image->pixels[i], image->pixels[i + 1], image->pixels[i + 2]) / 127.5f - 1.0f;
      min_z = std::min(min_z, n.z);
      worst_length_error = std::max(worst_length_error, std::abs(glm::length(n) - 1.0f));
      max_tilt_x = std::max(max_tilt_x, std::abs(n.x));
      max_tilt_y = std::max(max_tilt_y, std::abs(n.y));
    }
    EXPECT_GT(min_z, 0.2f);
    EXPECT_LT(worst_length_error, 0.02f);  // 8-bit quantisation: about 1/127 per channel
    // The map really tilts the normal, both ways (a flat map would be pointless).
    EXPECT_GT(max_tilt_x, 0.3f);
    EXPECT_GT(max_tilt_y, 0.3f);
  }
}

// glTF's tangent convention (spec, "Meshes"): xyz is unit, orthogonal to the normal and
// points along increasing u; w = +-1 makes cross(N, T) * w point along decreasing v. The
// stored tangents must agree with the directions the UVs give on every triangle.
TEST_F(StillLife, TangentsFollowTheUvsOfEveryTexturedTriangle) {
  const Scene& s = scene();
  std::set<std::uint32_t> textured;
  for (const char* name : {"bricks", "floor_tiles", "glazed_torus", "hammered_copper"})
    textured.insert(material_index(s, material_named(s, name)));
  std::size_t checked = 0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    if (!textured.count(s.material_id[t])) continue;
    SCOPED_TRACE("triangle " + std::to_string(t));
    ASSERT_EQ(s.attrib_flags[t] & (kHasNormals | kHasTexcoords | kHasTangents),
              kHasNormals | kHasTexcoords | kHasTangents);
    const glm::vec3 e1 = s.triangles.vertex(t, 1) - s.triangles.vertex(t, 0);
    const glm::vec3 e2 = s.triangles.vertex(t, 2) - s.triangles.vertex(t, 0);
    const glm::vec2 d1 = s.texcoords[3 * t + 1] - s.texcoords[3 * t], d2 = s.texcoords[3 * t + 2] - s.texcoords[3 * t];
    const float det = d1.x * d2.y - d2.x * d1.y;
    ASSERT_NE(det, 0.0f) << "zero UV area";
    const glm::vec3 dpdu = glm::normalize((d2.y * e1 - d1.y * e2) / det);
    const glm::vec3 dpdv = glm::normalize((d1.x * e2 - d2.x * e1) / det);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = s.normals[3 * t + std::size_t(k)];
      const glm::vec4 tan = s.tangents[3 * t + std::size_t(k)];
      const glm::vec3 tv(tan);
      EXPECT_NEAR(glm::length(tv), 1.0f, 1e-4f);
      EXPECT_NEAR(glm::dot(tv, n), 0.0f, 1e-4f);
      EXPECT_EQ(std::abs(tan.w), 1.0f);
      // Per-vertex tangents of a curved mesh differ a little from the face's UV
      // gradient; a tangent off by a quarter turn or flipped would fail these.
      EXPECT_GT(glm::dot(tv, dpdu), 0.9f);
      EXPECT_GT(glm::dot(glm::cross(n, tv) * tan.w, -dpdv), 0.9f);
    }
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(CornellBoxDof, ThinLensFocusedOnTheMiddleSphere) {
  const Scene s = load_scene(test::scenes_dir() / "cornell-box-dof.gltf");
  ASSERT_EQ(s.cameras.size(), 1u);
  const CameraDesc& cam = s.cameras[0];
  ASSERT_TRUE(cam.aperture_radius.has_value());
  ASSERT_TRUE(cam.focus_distance.has_value());
  EXPECT_GT(*cam.aperture_radius, 0.0f);
  const glm::vec3 eye(cam.camera_to_world[3]);
  const glm::vec3 forward = -glm::normalize(glm::vec3(cam.camera_to_world[2]));
  std::vector<float> depths;  // of each sphere's centre along the view axis
  for (const char* name : {"yellow_plastic", "mirror", "blue_matte"}) {
    const std::uint32_t id = material_index(s, material_named(s, name));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (std::size_t t = 0; t < s.triangle_count(); ++t)
      if (s.material_id[t] == id)
        for (int k = 0; k < 3; ++k) {
          lo = glm::min(lo, s.triangles.vertex(t, k));
          hi = glm::max(hi, s.triangles.vertex(t, k));
        }
    ASSERT_LT(lo.x, hi.x) << name << " has no triangles";
    depths.push_back(glm::dot(0.5f * (lo + hi) - eye, forward));
  }
  EXPECT_NEAR(*cam.focus_distance, depths[1], 1e-3f) << "focus on the middle (mirror) sphere";
  // The other two lie well in front of and behind the plane in focus: at least 5 pixels
  // of blur on a 512-pixel image (blur angle 2 r |1/d - 1/f|, pixel 2 tan(yfov/2) / 512).
  const float pixel = 2.0f * std::tan(0.5f * cam.yfov) / 512.0f;
  for (float d : {depths[0], depths[2]}) {
    const float blur_pixels = 2.0f * *cam.aperture_radius * std::abs(1.0f / d - 1.0f / *cam.focus_distance) / pixel;
    EXPECT_GT(blur_pixels, 5.0f) << "depth " << d;
  }
  EXPECT_LT(depths[0], depths[1]);
  EXPECT_GT(depths[2], depths[1]);
}

}  // namespace
}  // namespace lancer
