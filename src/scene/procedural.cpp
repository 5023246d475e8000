#include "scene/procedural.h"

#include "simd/splitmix64.h"
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "scene/scene_builder.h"
#include "scene/scene_error.h"

namespace lancer {

namespace {

// Large enough for any benchmark, small enough that a typo cannot ask for terabytes.
constexpr std::size_t kMaxTriangles = std::size_t(1) << 24;

// A mesh whose corners are computed once and referenced by index, so triangles that
// share a vertex share its exact bits.
struct IndexedMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

std::string scene_name(const Scene& scene, const char* generator) {
  return scene.source.empty() ? std::string("procedural ") + generator : scene.source;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The same zero-area test as SceneBuilder::add_triangle (cross product in double).
bool zero_area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 e1 = glm::dvec3(b) - glm::dvec3(a);
  const glm::dvec3 e2 = glm::dvec3(c) - glm::dvec3(a);
  return glm::cross(e1, e2) == glm::dvec3(0.0);
}

void check_material(const Scene& scene, std::uint32_t material, const std::string& name) {
  const bool ok = material < scene.materials.size() || (scene.materials.empty() && material == 0);
  if (!ok)
    throw SceneError(name, "material id " + std::to_string(material) + " does not exist (the scene has " +
                               std::to_string(scene.materials.size()) + " materials)");
}

void check_sphere_args(glm::vec3 center, float radius, const std::string& name) {
  if (!finite(center)) throw SceneError(name, "sphere centre is not finite");
  if (!(radius > 0.0f) || !std::isfinite(radius))
    throw SceneError(name, "sphere radius must be positive and finite, got " + std::to_string(radius));
}

// Adds the whole mesh or nothing: a triangle that float rounding collapsed would be
// dropped by SceneBuilder and leave a hole, so it is refused before anything is added.
void append_indexed(Scene& scene, const IndexedMesh& mesh, std::uint32_t material, const std::string& name) {
  for (const auto& t : mesh.triangles)
    if (zero_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]))
      throw SceneError(name, "a triangle collapsed to zero area in single precision (size too small for its position)");

  // No reserve here: exact reserves on repeated appends would defeat geometric growth.
  SceneBuilder builder(scene, name);
  const auto first_id = static_cast<std::uint32_t>(scene.source_triangle_id.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const glm::vec3 p[3] = {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
    CornerAttributes attribs;
    glm::vec3 n[3];
    if (!mesh.normals.empty()) {
      for (int k = 0; k < 3; ++k) n[k] = mesh.normals[t[k]];
      attribs.normals = n;
    }
    builder.add_triangle(p, material, first_id + static_cast<std::uint32_t>(i), attribs);
  }
  builder.finish();
}

// A point on the sphere, rounded to float once: every triangle using it gets these bits.
glm::vec3 sphere_point(glm::vec3 center, float radius, const glm::dvec3& unit) {
  return glm::vec3(glm::dvec3(center) + double(radius) * unit);
}

std::uint32_t add_sphere_vertex(IndexedMesh& mesh, glm::vec3 center, float radius, const glm::dvec3& unit,
                                bool smooth) {
  mesh.positions.push_back(sphere_point(center, radius, unit));
  if (smooth) mesh.normals.push_back(glm::vec3(unit));
  return static_cast<std::uint32_t>(mesh.positions.size() - 1);
}


}  // namespace

void append_uv_sphere(Scene& scene, glm::vec3 center, float radius, int slices, int stacks, std::uint32_t material,
                      bool smooth_normals) {
  const std::string name = scene_name(scene, "uv sphere");
  check_sphere_args(center, radius, name);
  if (slices < 3) throw SceneError(name, "uv sphere needs at least 3 slices, got " + std::to_string(slices));
  if (stacks < 2) throw SceneError(name, "uv sphere needs at least 2 stacks, got " + std::to_string(stacks));
  if (2.0 * double(slices) * double(stacks - 1) > double(kMaxTriangles))
    throw SceneError(name, "uv sphere of " + std::to_string(slices) + " x " + std::to_string(stacks) +
                               " would exceed " + std::to_string(kMaxTriangles) + " triangles");
  check_material(scene, material, name);

  // theta from the +y pole, phi around y; the direction (sin t cos p, cos t, -sin t sin p)
  // turns counter-clockwise seen from +y as phi grows, which fixes the winding below.
  constexpr double kPi = 3.14159265358979323846;
  IndexedMesh mesh;
  const std::uint32_t north = add_sphere_vertex(mesh, center, radius, {0.0, 1.0, 0.0}, smooth_normals);
  // ring(i, j): vertex j of ring i (1 <= i < stacks); j == slices wraps to the seam column 0.
  const std::uint32_t first_ring = static_cast<std::uint32_t>(mesh.positions.size());
  for (int i = 1; i < stacks; ++i) {
    const double theta = kPi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * kPi * j / slices;
      const glm::dvec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      add_sphere_vertex(mesh, center, radius, unit, smooth_normals);
    }
  }
  const std::uint32_t south = add_sphere_vertex(mesh, center, radius, {0.0, -1.0, 0.0}, smooth_normals);
  const auto ring = [&](int i, int j) {
    return first_ring + static_cast<std::uint32_t>((i - 1) * slices + (j % slices));
  };

  for (int j = 0; j < slices; ++j) mesh.triangles.push_back({north, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < slices; ++j) mesh.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
  append_indexed(scene, mesh, material, name);
}

void append_icosphere(Scene& scene, glm::vec3 center, float radius, int subdivisions, std::uint32_t material) {
  const std::string name = scene_name(scene, "icosphere");
  check_sphere_args(center, radius, name);
  if (subdivisions < 0 || subdivisions > 8)
    throw SceneError(name, "icosphere subdivisions must be in 0..8, got " + std::to_string(subdivisions));
  check_material(scene, material, name);

  // The icosahedron's 12 corners are the cyclic permutations of (0, +-1, +-phi). Its
  // 20 faces are the corner triples at mutual distance 2 (the edge length); other
  // distances are about 3.24, so the threshold 5 on the squared distance is safe.
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> unit;
  for (double a : {-1.0, 1.0})
    for (double b : {-phi, phi}) {
      unit.emplace_back(0.0, a, b);
      unit.emplace_back(a, b, 0.0);
      unit.emplace_back(b, 0.0, a);
    }
  for (auto& u : unit) u = glm::normalize(u);
  const auto adjacent = [&](std::size_t i, std::size_t j) {
    const glm::dvec3 d = unit[i] - unit[j];
    return glm::dot(d, d) * (1.0 + phi * phi) < 5.0;  // squared distance before normalising
  };
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (std::uint32_t i = 0; i < 12; ++i)
    for (std::uint32_t j = i + 1; j < 12; ++j)
      for (std::uint32_t k = j + 1; k < 12; ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        const glm::dvec3 n = glm::cross(unit[j] - unit[i], unit[k] - unit[i]);
        if (glm::dot(n, unit[i] + unit[j] + unit[k]) > 0.0)
          faces.push_back({i, j, k});
        else
          faces.push_back({i, k, j});
      }

  // Plain 1-to-4 split (no smoothing); each edge's midpoint is made once (keyed by its sorted
  // endpoints) so the two triangles beside the edge share it.
  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t(a < b ? a : b) << 32) | (a < b ? b : a);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      unit.push_back(glm::normalize(unit[a] + unit[b]));
      const auto index = static_cast<std::uint32_t>(unit.size() - 1);
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const std::uint32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({ab, f[1], bc});
      finer.push_back({ca, bc, f[2]});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }

  IndexedMesh mesh;
  mesh.positions.reserve(unit.size());
  mesh.normals.reserve(unit.size());
  for (const auto& u : unit) {
    mesh.positions.push_back(sphere_point(center, radius, u));
    mesh.normals.push_back(glm::vec3(u));
  }
  mesh.triangles = std::move(faces);
  append_indexed(scene, mesh, material, name);
}

void append_quad(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, std::uint32_t material) {
  const std::string name = scene_name(scene, "quad");
  check_material(scene, material, name);
  IndexedMesh mesh;
  mesh.positions = {p0, p1, p2, p3};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& p : mesh.positions)
    if (!finite(p)) throw SceneError(name, "quad corner is not finite");
  append_indexed(scene, mesh, material, name);
}

void append_box(Scene& scene, const Bounds3& box, std::uint32_t material) {
  const std::string name = scene_name(scene, "box");
  if (!finite(box.lo) || !finite(box.hi)) throw SceneError(name, "box bounds are not finite");
  if (!(box.lo.x < box.hi.x && box.lo.y < box.hi.y && box.lo.z < box.hi.z))
    throw SceneError(name, "box needs a positive extent on every axis");
  check_material(scene, material, name);

  // Corner c has x from bit 0, y from bit 1, z from bit 2 (0: lo, 1: hi).
  IndexedMesh mesh;
  for (int c = 0; c < 8; ++c)
    mesh.positions.emplace_back((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                                (c & 4) ? box.hi.z : box.lo.z);
  // Each face walks its four corners around the face; it is flipped when that order
  // is clockwise seen from outside.
  const glm::vec3 centre = box.center();
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t base = side ? (1u << axis) : 0u;
      std::array<std::uint32_t, 4> q = {base, base + u, base + u + v, base + v};
      const glm::vec3 a = mesh.positions[q[0]], b = mesh.positions[q[1]], c = mesh.positions[q[2]];
      if (glm::dot(glm::cross(b - a, c - a), a - centre) < 0.0f) std::swap(q[1], q[3]);
      mesh.triangles.push_back({q[0], q[1], q[2]});
      mesh.triangles.push_back({q[0], q[2], q[3]});
    }
  }
  append_indexed(scene, mesh, material, name);
}

Scene make_random_triangle_soup(std::size_t count, std::uint64_t seed, Bounds3 box, float max_edge) {
  Scene scene;
  scene.source = "random triangle soup (seed " + std::to_string(seed) + ")";
  const std::string& name = scene.source;
  if (count > kMaxTriangles)
    throw SceneError(name, std::to_string(count) + " triangles requested, at most " +
                               std::to_string(kMaxTriangles) + " allowed");
  if (!finite(box.lo) || !finite(box.hi) || box.empty()) throw SceneError(name, "box is empty or not finite");
  if (!(max_edge > 0.0f) || !std::isfinite(max_edge))
    throw SceneError(name, "max_edge must be positive and finite, got " + std::to_string(max_edge));

  // Corners are drawn in the ball of radius max_edge / 2 around a centre inside the
  // box, so no edge exceeds max_edge; clamping into the box only shortens edges.
  SplitMix64 rng(seed);
  const glm::vec3 extent = box.hi - box.lo;
  const float half = 0.5f * max_edge;
  // Draws are sequenced one statement each: the evaluation order of function
  // arguments is unspecified, and would make the stream compiler-dependent.
  const auto uniform3 = [&] {
    glm::vec3 u;
    u.x = rng.uniform();
    u.y = rng.uniform();
    u.z = rng.uniform();
    return u;
  };
  const auto in_box = [&] { return box.lo + uniform3() * extent; };
  const auto in_unit_ball = [&] {
    for (;;) {
      const glm::vec3 v = 2.0f * uniform3() - 1.0f;
      if (glm::dot(v, v) <= 1.0f) return v;  // accepted with probability pi/6
    }
  };

  SceneBuilder builder(scene, name);
  scene.triangles.reserve(count);
  constexpr int kMaxAttempts = 1000;
  for (std::size_t i = 0; i < count; ++i) {
    int attempts = 0;
    glm::vec3 p[3];
    do {
      if (++attempts > kMaxAttempts)
        throw SceneError(name, "could not place a non-degenerate triangle in a box this flat");
      const glm::vec3 c = in_box();
      for (auto& corner : p) corner = glm::clamp(c + half * in_unit_ball(), box.lo, box.hi);
    } while (zero_area(p[0], p[1], p[2]));
    builder.add_triangle(p, 0, static_cast<std::uint32_t>(i));
  }
  builder.finish();
  return scene;
}

}  // namespace lancer
