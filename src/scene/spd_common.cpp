#include "scene/spd_common.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "scene/procedural.h"
#include "scene/scene_error.h"

namespace lancer::spd {

namespace {

glm::vec3 to_float(const glm::dvec3& v) { return glm::vec3(v); }

}  // namespace

glm::dmat3 rotation(const glm::dvec3& axis, double angle) {
  // K v = axis x v; R = I + sin(angle) K + (1 - cos(angle)) K^2.
  const glm::dmat3 k(glm::dvec3(0.0, axis.z, -axis.y), glm::dvec3(-axis.z, 0.0, axis.x),
                     glm::dvec3(axis.y, -axis.x, 0.0));
  return glm::dmat3(1.0) + std::sin(angle) * k + (1.0 - std::cos(angle)) * (k * k);
}

std::uint64_t sphere_triangles(const SpdOptions& options) { return 20ull << (2 * options.sphere_subdivisions); }

std::uint64_t cylinder_triangles(const SpdOptions& options) { return 4ull * std::uint64_t(options.cylinder_sides); }

Material diffuse_material(std::string name, glm::vec3 colour) {
  Material m;
  m.name = std::move(name);
  m.base_color = glm::vec4(colour, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  // SPD's NFF polygons follow no winding convention (renderers of the databases shade both
  // sides), so no side is culled.
  m.double_sided = true;
  return m;
}

Material mirror_material(std::string name, glm::vec3 colour) {
  Material m = diffuse_material(std::move(name), colour);
  m.metallic = 1.0f;
  m.roughness = 0.1f;
  return m;
}

Material glass_material(std::string name, glm::vec3 colour, float transmission, float ior) {
  Material m = diffuse_material(std::move(name), colour);
  m.roughness = 0.0f;
  m.transmission = transmission;
  m.thickness = 1.0f;  // solid glass: a volume boundary that refracts, not a glTF thin wall
  m.ior = ior;
  return m;
}

SpdEmitter::SpdEmitter(Scene& scene, std::string name, int size, std::uint64_t expected, const SpdOptions& options)
    : scene_(scene),
      name_(std::move(name)),
      expected_(expected),
      builder_(scene, "spd " + name_),
      cylinder_sides_(options.cylinder_sides),
      sphere_subdivisions_(options.sphere_subdivisions) {
  scene_.source = "spd " + name_ + " (size " + std::to_string(size) + ")";
  // The count is known and capped, so reserve once instead of growing (which would
  // briefly need twice the memory at the top sizes).
  const auto n = static_cast<std::size_t>(expected);
  scene_.triangles.reserve(n);
  scene_.material_id.reserve(n);
  scene_.source_triangle_id.reserve(n);
  scene_.attrib_flags.reserve(n);  // normals, where a generator has them, follow (scene_builder.cpp)
}

std::uint32_t SpdEmitter::add_material(const Material& material) {
  scene_.materials.push_back(material);
  return static_cast<std::uint32_t>(scene_.materials.size() - 1);
}

void SpdEmitter::add(const glm::dvec3 p[3], const glm::dvec3* n, std::uint32_t material) {
  // to_scene is a mirror: reversing the corner order keeps the front side in front.
  const glm::vec3 q[3] = {to_float(to_scene(p[0])), to_float(to_scene(p[2])), to_float(to_scene(p[1]))};
  CornerAttributes attribs;
  glm::vec3 normals[3];
  if (n) {
    normals[0] = to_float(to_scene(n[0]));
    normals[1] = to_float(to_scene(n[2]));
    normals[2] = to_float(to_scene(n[1]));
    attribs.normals = normals;
  }
  builder_.add_triangle(q, material, next_id_++, attribs);
}

void SpdEmitter::triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::uint32_t material) {
  const glm::dvec3 p[3] = {a, b, c};
  add(p, nullptr, material);
}

void SpdEmitter::triangle(const glm::dvec3 p[3], const glm::dvec3 n[3], std::uint32_t material) { add(p, n, material); }

void SpdEmitter::quad(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                      std::uint32_t material) {
  triangle(a, b, c, material);
  triangle(a, c, d, material);
}

void SpdEmitter::sphere(const glm::dvec3& centre, double radius, std::uint32_t material) {
  if (sphere_corners_.empty()) {
    // One unit icosphere from procedural.h, instanced below: every sphere then shares
    // its closed topology, and equal template corners give equal output bits.
    Scene unit;
    append_icosphere(unit, glm::vec3(0.0f), 1.0f, sphere_subdivisions_, 0);
    sphere_corners_.reserve(3 * unit.triangle_count());
    sphere_normals_.reserve(3 * unit.triangle_count());
    for (std::size_t t = 0; t < unit.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k) {
        sphere_corners_.emplace_back(unit.triangles.vertex(t, k));
        sphere_normals_.emplace_back(unit.normals[3 * t + std::size_t(k)]);
      }
  }
  for (std::size_t i = 0; i < sphere_corners_.size(); i += 3) {
    const glm::dvec3 p[3] = {centre + radius * sphere_corners_[i], centre + radius * sphere_corners_[i + 1],
                             centre + radius * sphere_corners_[i + 2]};
    add(p, &sphere_normals_[i], material);
  }
}

void SpdEmitter::cylinder(const glm::dvec3& base, const glm::dvec3& apex, double radius, std::uint32_t material) {
  // (u, v, axis) is right-handed, so the ring angle grows counter-clockwise seen from
  // the apex; that fixes the corner orders below.
  const glm::dvec3 axis = glm::normalize(apex - base);
  const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, axis));
  const glm::dvec3 v = glm::cross(axis, u);
  const int k = cylinder_sides_;
  std::vector<glm::dvec3> radial(std::size_t(k) + 1), bottom(std::size_t(k) + 1), top(std::size_t(k) + 1);
  for (int j = 0; j < k; ++j) {
    const double angle = 2.0 * std::numbers::pi * j / k;
    radial[std::size_t(j)] = std::cos(angle) * u + std::sin(angle) * v;
    bottom[std::size_t(j)] = base + radius * radial[std::size_t(j)];
    top[std::size_t(j)] = apex + radius * radial[std::size_t(j)];
  }
  // The seam reuses column 0, so the ring closes on identical corners.
  radial[std::size_t(k)] = radial[0];
  bottom[std::size_t(k)] = bottom[0];
  top[std::size_t(k)] = top[0];
  for (std::size_t j = 0; j < std::size_t(k); ++j) {
    const glm::dvec3 side1[3] = {bottom[j], bottom[j + 1], top[j + 1]};
    const glm::dvec3 n1[3] = {radial[j], radial[j + 1], radial[j + 1]};
    add(side1, n1, material);
    const glm::dvec3 side2[3] = {bottom[j], top[j + 1], top[j]};
    const glm::dvec3 n2[3] = {radial[j], radial[j + 1], radial[j]};
    add(side2, n2, material);
  }
  const glm::dvec3 up[3] = {axis, axis, axis};
  const glm::dvec3 down[3] = {-axis, -axis, -axis};
  for (std::size_t j = 0; j < std::size_t(k); ++j) {
    const glm::dvec3 cap_top[3] = {apex, top[j], top[j + 1]};
    add(cap_top, up, material);
    const glm::dvec3 cap_bottom[3] = {base, bottom[j + 1], bottom[j]};
    add(cap_bottom, down, material);
  }
}

void SpdEmitter::set_view(const View& view) {
  const glm::dvec3 from = to_scene(view.from);
  const glm::dvec3 forward = glm::normalize(to_scene(view.at) - from);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, to_scene(view.up)));
  const glm::dvec3 up = glm::cross(right, forward);
  CameraDesc camera;
  camera.name = "spd " + name_ + " view";
  camera.camera_to_world = glm::mat4(glm::vec4(glm::vec3(right), 0.0f), glm::vec4(glm::vec3(up), 0.0f),
                                     glm::vec4(glm::vec3(-forward), 0.0f), glm::vec4(glm::vec3(from), 1.0f));
  camera.yfov = static_cast<float>(view.fov_degrees * std::numbers::pi / 180.0);
  camera.aspect_ratio = 1.0f;
  camera.index = int(scene_.cameras.size());
  scene_.cameras.push_back(camera);
}

void SpdEmitter::add_lights(const std::vector<glm::dvec3>& positions, const glm::dvec3& look_at) {
  const double n = static_cast<double>(positions.size());
  const double relative = std::sqrt(n) / (2.0 * n);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3 to_target = positions[i] - look_at;
    PunctualLight light;
    light.name = "spd " + name_ + " light " + std::to_string(i);
    light.type = LightType::Point;
    light.position = glm::vec3(to_scene(positions[i]));
    light.intensity = static_cast<float>(relative * std::numbers::pi * glm::dot(to_target, to_target));
    scene_.lights.push_back(light);
  }
}

void SpdEmitter::finish() {
  builder_.finish();
  if (scene_.stats.degenerate_dropped > 0)
    throw SceneError("spd " + name_, std::to_string(scene_.stats.degenerate_dropped) +
                                         " triangles collapsed to zero area in single precision "
                                         "(lower the tessellation)");
  if (scene_.triangle_count() != expected_)
    throw std::logic_error("spd " + name_ + ": built " + std::to_string(scene_.triangle_count()) +
                           " triangles, but the documented formula gives " + std::to_string(expected_));
}

}  // namespace lancer::spd
