// Pieces the SPD generators share: the SPD -> scene frame mirror, tessellated spheres
// and cylinders, the surface mapping onto glTF materials, and the viewpoint and lights.
// Internal to src/scene/spd_*.cpp; the public interface is spd.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"
#include "scene/scene_builder.h"
#include "scene/spd.h"

namespace lancer::spd {

// The SPD models with +z up in a left-handed frame; swapping y and z is a mirror that
// lands in glTF's right-handed +y-up frame (see spd.h).
inline glm::dvec3 to_scene(const glm::dvec3& p) { return {p.x, p.z, p.y}; }

// The rotation by `angle` radians about the unit vector `axis`, counter-clockwise seen
// from the axis' tip (Rodrigues' formula).
glm::dmat3 rotation(const glm::dvec3& axis, double angle);

std::uint64_t sphere_triangles(const SpdOptions& options);    // 20 * 4^s
std::uint64_t cylinder_triangles(const SpdOptions& options);  // 4 * k

// The SPD gives each surface a colour and Phong-style coefficients (diffuse Kd,
// specular Ks, transmission T, index of refraction). Lancer's Whitted integrator reads
// glTF metallic-roughness, so: T > 0 becomes a smooth dielectric (KHR_materials_
// transmission T, KHR_materials_ior), Ks >= 0.5 a mirror (metallic 1, roughness 0.1,
// base colour as its reflectance), anything else a diffuse surface (metallic 0,
// roughness 1). Colours are taken as linear.
Material diffuse_material(std::string name, glm::vec3 colour);
Material mirror_material(std::string name, glm::vec3 colour);
Material glass_material(std::string name, glm::vec3 colour, float transmission, float ior);

// An NFF viewpoint: eye, look-at point, up vector and full field of view (the SPD
// renders square images, so vertical and horizontal fields are equal).
struct View {
  glm::dvec3 from;
  glm::dvec3 at;
  glm::dvec3 up;
  double fov_degrees = 45.0;
};

// Adds an SPD database to a Scene: everything is given in SPD coordinates and mapped
// by to_scene here, with the corner order reversed (the mirror flips the winding), so
// each piece keeps its outward orientation. Counts what it adds and, in finish(),
// checks the count against the documented formula and that no triangle collapsed.
class SpdEmitter {
 public:
  // `name` is the generator name (messages say "spd <name>"); `expected` the triangle
  // count from the formula, reserved up front.
  SpdEmitter(Scene& scene, std::string name, int size, std::uint64_t expected, const SpdOptions& options);

  std::uint32_t add_material(const Material& material);

  // A triangle counter-clockwise seen from its front side.
  void triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::uint32_t material);
  // The same with a shading normal per corner.
  void triangle(const glm::dvec3 p[3], const glm::dvec3 n[3], std::uint32_t material);
  // Two triangles (a, b, c) and (a, c, d) of a planar quad counter-clockwise from its front.
  void quad(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d, std::uint32_t material);

  // A closed icosphere (S triangles) with smooth normals.
  void sphere(const glm::dvec3& centre, double radius, std::uint32_t material);
  // A closed cylinder (C triangles) from `base` to `apex`: k side quads with smooth
  // normals and two caps fanned around their centres with flat normals.
  void cylinder(const glm::dvec3& base, const glm::dvec3& apex, double radius, std::uint32_t material);

  // Camera 0 from the SPD viewpoint, aspect ratio 1.
  void set_view(const View& view);

  // Point lights at `positions`, white. The SPD leaves intensities to the renderer and
  // suggests a relative intensity r = sqrt(n) / (2n) for n lights; each light gets
  // r * pi * d^2 candela, d its distance to the look-at point, so a white diffuse
  // surface there, facing the light, has radiance r.
  void add_lights(const std::vector<glm::dvec3>& positions, const glm::dvec3& look_at);

  // Closes the scene: default material check, count and zero-area checks.
  void finish();

 private:
  void add(const glm::dvec3 p[3], const glm::dvec3* n, std::uint32_t material);

  Scene& scene_;
  std::string name_;
  std::uint64_t expected_;
  SceneBuilder builder_;
  std::uint32_t next_id_ = 0;
  int cylinder_sides_;
  int sphere_subdivisions_;
  // The unit icosphere, three corners per triangle, and its unit normals; made on the
  // first sphere.
  std::vector<glm::dvec3> sphere_corners_;
  std::vector<glm::dvec3> sphere_normals_;
};

// One database: its name, valid sizes, triangle-count formula (size and options
// already checked) and builder (which adds exactly that many triangles).
struct Generator {
  const char* name;
  SpdSizeRange sizes;
  std::uint64_t (*triangles)(int size, const SpdOptions& options);
  void (*build)(SpdEmitter& emitter, int size);
};

// Defined in spd_balls.cpp, spd_gears.cpp, spd_mount.cpp, spd_rings.cpp, spd_tetra.cpp.
extern const Generator kBalls;
extern const Generator kGears;
extern const Generator kMount;
extern const Generator kRings;
extern const Generator kTetra;

}  // namespace lancer::spd
