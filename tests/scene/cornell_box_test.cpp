// The Cornell box scene files (scenes/*.gltf, written by scripts/make_cornell_box.py)
// loaded through load_scene: the published geometry in metres, inward-facing walls,
// the light's radiance, the camera of the original data, and the classic view (red
// wall on the camera's left, green on its right).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

constexpr float kMetre = 0.001f;  // the published data are in millimetres
const glm::vec3 kBoxCentre(0.278f, 0.2744f, 0.2796f);

Scene load(const char* file) { return load_scene(test::scenes_dir() / file); }

std::uint32_t material_named(const Scene& s, const std::string& name) {
  for (std::size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return static_cast<std::uint32_t>(i);
  ADD_FAILURE() << "no material named '" << name << "'";
  return ~0u;
}

std::vector<std::size_t> triangles_with(const Scene& s, std::uint32_t material) {
  std::vector<std::size_t> result;
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    if (s.material_id[t] == material) result.push_back(t);
  return result;
}

glm::vec3 centroid(const Scene& s, std::size_t t) {
  return (s.triangles.vertex(t, 0) + s.triangles.vertex(t, 1) + s.triangles.vertex(t, 2)) / 3.0f;
}

glm::vec3 centroid(const Scene& s, const std::vector<std::size_t>& tris) {
  glm::vec3 sum(0.0f);
  for (std::size_t t : tris) sum += centroid(s, t);
  return sum / float(tris.size());
}

glm::vec3 unit_normal(const Scene& s, std::size_t t) {
  const glm::vec3 a = s.triangles.vertex(t, 0), b = s.triangles.vertex(t, 1), c = s.triangles.vertex(t, 2);
  return glm::normalize(glm::cross(b - a, c - a));
}

glm::vec3 to_camera(const CameraDesc& camera, glm::vec3 world) {
  return glm::vec3(glm::inverse(camera.camera_to_world) * glm::vec4(world, 1.0f));
}

// Every undirected edge used by exactly two of the triangles, once in each direction,
// with vertices compared by their exact bits.
bool closed_mesh(const Scene& s, const std::vector<std::size_t>& tris) {
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;
  std::map<Key, int> ids;
  std::map<std::pair<int, int>, int> directed;
  for (std::size_t t : tris) {
    int v[3];
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      std::uint32_t b[3];
      std::memcpy(b, &p, sizeof b);
      v[k] = ids.emplace(Key{b[0], b[1], b[2]}, int(ids.size())).first->second;
    }
    for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
  }
  for (const auto& [edge, uses] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (uses != 1 || reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

void expect_vec_near(glm::vec3 actual, glm::vec3 expected, float tol, const std::string& what) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual[k], expected[k], tol) << what << " component " << k;
}

void expect_diffuse(const Material& m, glm::vec3 rgb) {
  expect_vec_near(glm::vec3(m.base_color), rgb, 1e-6f, m.name);
  EXPECT_EQ(m.metallic, 0.0f) << m.name;
  EXPECT_EQ(m.roughness, 1.0f) << m.name;
  EXPECT_FALSE(m.emissive()) << m.name;
}

// The parts both files share: walls, light, materials, camera.
void expect_common_box(const Scene& s) {
  SCOPED_TRACE(s.source);
  expect_diffuse(s.materials[material_named(s, "white")], {0.725f, 0.71f, 0.68f});
  expect_diffuse(s.materials[material_named(s, "red")], {0.63f, 0.065f, 0.05f});
  expect_diffuse(s.materials[material_named(s, "green")], {0.14f, 0.45f, 0.091f});

  // Light: radiance (17, 12, 4) as a normalised factor times KHR_materials_emissive_strength.
  const Material& light = s.materials[material_named(s, "light")];
  expect_vec_near(light.emission(), {17.0f, 12.0f, 4.0f}, 1e-5f * 17.0f, "light radiance");
  EXPECT_FLOAT_EQ(light.emissive_factor.x, 1.0f);
  EXPECT_FLOAT_EQ(light.emissive_strength, 17.0f);
  const auto light_tris = triangles_with(s, material_named(s, "light"));
  ASSERT_EQ(light_tris.size(), 2u);
  for (std::size_t t : light_tris) {
    expect_vec_near(unit_normal(s, t), {0.0f, -1.0f, 0.0f}, 1e-6f, "light faces down");
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      EXPECT_FLOAT_EQ(p.y, (548.8f - 0.1f) * kMetre) << "just below the ceiling";
      EXPECT_TRUE(std::abs(p.x - 0.213f) < 1e-6f || std::abs(p.x - 0.343f) < 1e-6f) << p.x;
      EXPECT_TRUE(std::abs(p.z - 0.227f) < 1e-6f || std::abs(p.z - 0.332f) < 1e-6f) << p.z;
    }
  }

  // The published extent: x up to 556.0 (ceiling), y 548.8, z 559.2 (back wall), in mm.
  const Bounds3 b = s.bounds();
  expect_vec_near(b.lo, {0.0f, 0.0f, 0.0f}, 1e-6f, "bounds lo");
  expect_vec_near(b.hi, {0.556f, 0.5488f, 0.5592f}, 1e-6f, "bounds hi");

  // Walls, floor and ceiling face into the box; flat NORMALs match the geometry.
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    ASSERT_TRUE(s.attrib_flags[t] & kHasNormals) << "triangle " << t << " has no NORMAL";
    const glm::vec3 c = centroid(s, t);
    const bool on_shell = c.y < 1e-6f || c.y > 0.5487f || c.z > 0.5591f || c.x < 1e-6f || c.x > 0.549f;
    if (on_shell && s.material_id[t] != material_named(s, "light")) {
      EXPECT_GT(glm::dot(unit_normal(s, t), kBoxCentre - c), 0.0f) << "wall triangle " << t << " faces out";
    }
  }

  // One camera, as in the data: at (278, 273, -800) mm looking along +z, yfov 2 atan(12.5 / 35).
  ASSERT_EQ(s.cameras.size(), 1u);
  const CameraDesc& cam = s.cameras[0];
  EXPECT_NEAR(cam.yfov, 2.0 * std::atan(0.0125 / 0.035), 1e-6);
  ASSERT_TRUE(cam.aspect_ratio.has_value());
  EXPECT_FLOAT_EQ(*cam.aspect_ratio, 1.0f);
  expect_vec_near(glm::vec3(cam.camera_to_world[3]), {0.278f, 0.273f, -0.8f}, 1e-6f, "camera position");
  expect_vec_near(glm::vec3(cam.camera_to_world * glm::vec4(0, 0, -1, 0)), {0, 0, 1}, 1e-6f, "camera forward");
  expect_vec_near(glm::vec3(cam.camera_to_world * glm::vec4(0, 1, 0, 0)), {0, 1, 0}, 1e-6f, "camera up");

  // The classic view, not its mirror image: red on the left, green on the right.
  const glm::vec3 red = to_camera(cam, centroid(s, triangles_with(s, material_named(s, "red"))));
  const glm::vec3 green = to_camera(cam, centroid(s, triangles_with(s, material_named(s, "green"))));
  EXPECT_LT(red.x, -0.2f) << "red wall must be on the camera's left";
  EXPECT_GT(green.x, 0.2f) << "green wall must be on the camera's right";
  EXPECT_LT(red.z, 0.0f);
  EXPECT_LT(green.z, 0.0f);
}

TEST(CornellBox, GeometryMaterialsAndCamera) {
  const Scene s = load("cornell-box.gltf");
  // 5 walls + light (2 triangles each) + 2 blocks of 5 published faces.
  ASSERT_EQ(s.triangle_count(), 6u * 2u + 2u * 5u * 2u);
  EXPECT_EQ(s.stats.degenerate_dropped, 0u);
  expect_common_box(s);
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    expect_vec_near(s.normals[3 * t], unit_normal(s, t), 1e-5f, "flat NORMAL of triangle " + std::to_string(t));
}

TEST(CornellBox, BlocksInTheirPlacesFacingOutward) {
  const Scene s = load("cornell-box.gltf");
  ASSERT_EQ(s.cameras.size(), 1u);
  // The block faces are the white triangles off the shell; the tall one reaches 330 mm.
  std::vector<std::size_t> tall, shorter;
  for (std::size_t t : triangles_with(s, material_named(s, "white"))) {
    const glm::vec3 c = centroid(s, t);
    if (c.y < 1e-6f || c.y > 0.5487f || c.z > 0.5591f) continue;  // floor, ceiling, back wall
    float top = 0.0f;
    for (int k = 0; k < 3; ++k) top = std::max(top, s.triangles.vertex(t, k).y);
    (top > 0.2f ? tall : shorter).push_back(t);
  }
  ASSERT_EQ(tall.size(), 10u);
  ASSERT_EQ(shorter.size(), 10u);
  for (const auto* block : {&tall, &shorter}) {
    const glm::vec3 centre = centroid(s, *block);
    float top = 0.0f;
    for (std::size_t t : *block) {
      EXPECT_GT(glm::dot(unit_normal(s, t), centroid(s, t) - centre), 0.0f) << "block face " << t << " faces in";
      for (int k = 0; k < 3; ++k) top = std::max(top, s.triangles.vertex(t, k).y);
    }
    EXPECT_FLOAT_EQ(top, block == &tall ? 330.0f * kMetre : 165.0f * kMetre);
  }
  // Tall block back left, short block front right, as seen by the camera.
  const glm::vec3 tall_cam = to_camera(s.cameras[0], centroid(s, tall));
  const glm::vec3 short_cam = to_camera(s.cameras[0], centroid(s, shorter));
  EXPECT_LT(tall_cam.x, 0.0f);
  EXPECT_GT(short_cam.x, 0.0f);
  EXPECT_LT(tall_cam.z, short_cam.z) << "tall block is farther from the camera";
}

TEST(CornellBoxSpheres, MirrorAndGlassSpheresOnTheFloor) {
  const Scene s = load("cornell-box-spheres.gltf");
  // The box without blocks, plus two 32 x 16 UV spheres of 2 * 32 * 15 triangles.
  ASSERT_EQ(s.triangle_count(), 6u * 2u + 2u * 960u);
  EXPECT_EQ(s.stats.degenerate_dropped, 0u);
  expect_common_box(s);

  const Material& mirror = s.materials[material_named(s, "mirror")];
  EXPECT_EQ(mirror.metallic, 1.0f);
  EXPECT_EQ(mirror.roughness, 0.0f);
  expect_vec_near(glm::vec3(mirror.base_color), glm::vec3(0.95f), 1e-6f, "mirror colour");
  EXPECT_EQ(mirror.transmission, 0.0f);
  const Material& glass = s.materials[material_named(s, "glass")];
  EXPECT_EQ(glass.metallic, 0.0f);
  EXPECT_EQ(glass.roughness, 0.0f);
  EXPECT_EQ(glass.transmission, 1.0f);
  EXPECT_FLOAT_EQ(glass.ior, 1.5f);

  glm::vec3 in_camera[2];
  int i = 0;
  for (const char* name : {"mirror", "glass"}) {
    SCOPED_TRACE(name);
    const auto tris = triangles_with(s, material_named(s, name));
    ASSERT_EQ(tris.size(), 960u);
    EXPECT_TRUE(closed_mesh(s, tris)) << "sphere has a hole or a flipped triangle";
    Bounds3 b;
    for (std::size_t t : tris) b.extend(s.triangles.triangle_bounds(t));
    const glm::vec3 centre = b.center();
    EXPECT_NEAR(b.lo.y, 0.0f, 1e-6f) << "rests on the floor";
    expect_vec_near(b.extent(), glm::vec3(0.2f), 1e-6f, "diameter");
    for (std::size_t t : tris) {
      ASSERT_TRUE(s.attrib_flags[t] & kHasNormals);
      EXPECT_GT(glm::dot(unit_normal(s, t), centroid(s, t) - centre), 0.0f) << "triangle " << t << " faces in";
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = s.triangles.vertex(t, k);
        EXPECT_NEAR(glm::distance(glm::dvec3(p), glm::dvec3(centre)), 0.1, 1e-6);
        // Smooth normals: radial at every corner.
        EXPECT_NEAR(glm::dot(s.normals[3 * t + k], glm::normalize(p - centre)), 1.0f, 1e-5f);
      }
    }
    in_camera[i++] = to_camera(s.cameras[0], centre);
  }
  EXPECT_LT(in_camera[0].x, 0.0f) << "mirror sphere on the left";
  EXPECT_GT(in_camera[1].x, 0.0f) << "glass sphere on the right";
  EXPECT_LT(in_camera[0].z, in_camera[1].z) << "mirror sphere at the back, glass in front";
}

}  // namespace
}  // namespace lancer

namespace lancer {
namespace {

// The motion scene: with the shutter open over its second, the ball and the short block
// move (one motion each) and nothing else does; the ball flies from left to right in the
// camera's view, and the block has turned 60 degrees by the close.
TEST(CornellBoxMotion, TheBallFliesAndTheShortBlockTurnsWhileTheShutterIsOpen) {
  const std::filesystem::path file = test::scenes_dir() / "cornell-box-motion.gltf";
  const Scene s = load_scene(file, std::nullopt, std::nullopt, InstancingMode::Auto, Shutter{0.0, 1.0});
  ASSERT_EQ(s.instancing.motions.size(), 2u);
  ASSERT_EQ(s.instancing.instances.size(), 3u);  // the still box, then the moving block and ball
  EXPECT_EQ(s.drawn_triangle_count(), 6u * 2u + 2u * 10u + 960u);
  const Instance& block = s.instancing.instances[1];
  const Instance& ball = s.instancing.instances[2];
  ASSERT_NE(block.motion, kNoHit);
  ASSERT_NE(ball.motion, kNoHit);
  const glm::vec3 start = instance_at(s.instancing, ball, 0.0f).to_world.offset;
  const glm::vec3 top = instance_at(s.instancing, ball, 0.5f).to_world.offset;
  const glm::vec3 end = instance_at(s.instancing, ball, 1.0f).to_world.offset;
  EXPECT_NEAR(start.x, 0.42f, 1e-6f);
  EXPECT_NEAR(top.y, 0.34f, 1e-6f);
  EXPECT_NEAR(end.x, 0.19f, 1e-6f);
  EXPECT_LT(to_camera(s.cameras[0], start).x, to_camera(s.cameras[0], end).x) << "left to right";
  // 60 degrees about +y: cos 60 on the diagonal's x entry.
  EXPECT_NEAR(instance_at(s.instancing, block, 1.0f).to_world.linear[0][0], 0.5f, 1e-6f);
  EXPECT_NEAR(instance_at(s.instancing, block, 0.0f).to_world.linear[0][0], 1.0f, 1e-6f);
}

}  // namespace
}  // namespace lancer
