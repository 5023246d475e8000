#include "scene/gltf_primitives.h"

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <utility>

#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer::gltf {

namespace {

// The vertex attributes of one primitive, already in world space.
struct WorldVertices {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;    // empty: the primitive has no NORMAL
  std::vector<glm::vec2> texcoords;  // empty: no TEXCOORD_0
  std::vector<glm::vec2> texcoords1; // empty: no TEXCOORD_1, or the material does not use it
  std::vector<glm::vec4> tangents;   // empty: no TANGENT (or no NORMAL, see below)
  std::vector<glm::vec4> colors;     // empty: no COLOR_0
};

int attribute(const tinygltf::Primitive& p, const char* name) {
  const auto it = p.attributes.find(name);
  return it == p.attributes.end() ? -1 : it->second;
}

// Reads the attributes and moves them to world space.
//  - Positions: world * (p, 1).
//  - Normals: by the inverse transpose of the upper 3x3 L. We use its cofactor
//    matrix cof(L) = det(L) * L^-T (columns l1 x l2, l2 x l0, l0 x l1), which is also
//    defined when L is singular, times sign(det L) so the direction is L^-T's. The
//    builder normalises.
//  - Tangents: xyz by L, normalised; w (bitangent sign) negated when det L < 0, as a
//    mirror turns the frame's handedness.
// glTF 2.0 spec, "Meshes": when NORMAL is absent, flat normals are used and TANGENT
// must be ignored.
// TEXCOORD_1 is read only when `want_texcoords1` (the material samples set 1).
WorldVertices world_vertices(const ModelRef& m, const tinygltf::Primitive& prim, const glm::dmat4& world,
                             bool want_texcoords1, const std::string& what) {
  WorldVertices v;
  const int position = attribute(prim, "POSITION");
  if (position < 0) throw SceneError(m.file, what + " has no POSITION attribute");
  v.positions = read_positions(m, position, what + " POSITION");
  const std::size_t n = v.positions.size();
  auto check_count = [&](std::size_t count, const char* name) {
    if (count != n)
      throw SceneError(m.file, what + " " + name + " has " + std::to_string(count) + " elements but POSITION has " +
                                   std::to_string(n));
  };
  if (const int a = attribute(prim, "NORMAL"); a >= 0) {
    v.normals = read_normals(m, a, what + " NORMAL");
    check_count(v.normals.size(), "NORMAL");
  }
  if (const int a = attribute(prim, "TEXCOORD_0"); a >= 0) {
    v.texcoords = read_texcoords(m, a, what + " TEXCOORD_0");
    check_count(v.texcoords.size(), "TEXCOORD_0");
  }
  if (const int a = attribute(prim, "TEXCOORD_1"); a >= 0 && want_texcoords1) {
    v.texcoords1 = read_texcoords(m, a, what + " TEXCOORD_1");
    check_count(v.texcoords1.size(), "TEXCOORD_1");
  }
  if (const int a = attribute(prim, "COLOR_0"); a >= 0) {
    v.colors = read_colors(m, a, what + " COLOR_0");
    check_count(v.colors.size(), "COLOR_0");
  }
  if (const int a = attribute(prim, "TANGENT"); a >= 0 && !v.normals.empty()) {
    v.tangents = read_tangents(m, a, what + " TANGENT");
    check_count(v.tangents.size(), "TANGENT");
  }

  const glm::dmat3 linear(world);
  const double sign = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
  const glm::dmat3 normal_matrix = sign * glm::dmat3(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                                                     glm::cross(linear[0], linear[1]));
  for (glm::vec3& p : v.positions) p = glm::vec3(world * glm::dvec4(p, 1.0));
  for (glm::vec3& nrm : v.normals) nrm = glm::vec3(normal_matrix * glm::dvec3(nrm));
  for (glm::vec4& t : v.tangents) {
    glm::dvec3 xyz = linear * glm::dvec3(t);
    const double len = glm::length(xyz);
    if (len > 0.0) xyz /= len;
    t = glm::vec4(glm::vec3(xyz), float(sign) * t.w);
  }
  return v;
}

// The vertex numbers of a primitive: its indices, checked against the vertex count,
// or 0..n-1 when it has none.
std::vector<std::uint32_t> vertex_numbers(const ModelRef& m, const tinygltf::Primitive& prim, std::size_t vertex_count,
                                          const std::string& what) {
  if (prim.indices < 0) {
    if (vertex_count > std::size_t(UINT32_MAX)) throw SceneError(m.file, what + " has too many vertices");
    std::vector<std::uint32_t> seq(vertex_count);
    for (std::size_t k = 0; k < vertex_count; ++k) seq[k] = std::uint32_t(k);
    return seq;
  }
  std::vector<std::uint32_t> indices = read_indices(m, prim.indices, what + " indices");
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (indices[k] >= vertex_count)
      throw SceneError(m.file, what + " indices: index " + std::to_string(indices[k]) + " at position " +
                                   std::to_string(k) + " is out of range (POSITION has " +
                                   std::to_string(vertex_count) + " vertices)");
  return indices;
}

// Triangle t of a primitive as positions in `numbers`, following the glTF 2.0 spec,
// "Topology types": triangles p_t = {3t, 3t+1, 3t+2}; strips
// p_t = {t, t + (1 + t%2), t + (2 - t%2)} (every other triangle swaps its last two
// vertices, keeping the winding); fans p_t = {t+1, t+2, 0}.
std::array<std::size_t, 3> triangle_corners(int mode, std::size_t t) {
  switch (mode) {
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      return {t, t + 1 + t % 2, t + 2 - t % 2};
    case TINYGLTF_MODE_TRIANGLE_FAN:
      return {t + 1, t + 2, 0};
    default:
      return {3 * t, 3 * t + 1, 3 * t + 2};
  }
}

}  // namespace

void PrimitiveEmitter::emit_mesh(int mesh, const glm::dmat4& world) {
  if (mesh < 0 || std::size_t(mesh) >= m_.model.meshes.size())
    throw SceneError(m_.file, "mesh index " + std::to_string(mesh) + " out of range (the file has " +
                                  std::to_string(m_.model.meshes.size()) + " meshes)");
  const std::size_t count = m_.model.meshes[std::size_t(mesh)].primitives.size();
  for (std::size_t p = 0; p < count; ++p) emit_primitive(mesh, int(p), world);
}

std::size_t PrimitiveEmitter::triangle_bound(int mesh) const {
  if (mesh < 0 || std::size_t(mesh) >= m_.model.meshes.size()) return 0;
  const auto& accessors = m_.model.accessors;
  std::size_t bound = 0;
  for (const tinygltf::Primitive& prim : m_.model.meshes[std::size_t(mesh)].primitives) {
    int counted = prim.indices;
    if (counted < 0) {
      const auto position = prim.attributes.find("POSITION");
      counted = position == prim.attributes.end() ? -1 : position->second;
    }
    if (counted >= 0 && std::size_t(counted) < accessors.size()) bound += accessors[std::size_t(counted)].count;
  }
  return bound;
}

std::uint32_t PrimitiveEmitter::material_id(int material, const std::string& what) {
  if (material >= 0) {
    if (std::size_t(material) >= m_.model.materials.size())
      throw SceneError(m_.file, what + ": material index " + std::to_string(material) + " out of range (the file has " +
                                    std::to_string(m_.model.materials.size()) + " materials)");
    return std::uint32_t(material);
  }
  if (!default_material_) {
    // glTF 2.0 spec, "Default Material": the material's defaults, i.e. white base
    // colour, metallic 1, roughness 1 (lancer::Material's own defaults).
    Material fallback;
    fallback.name = "glTF default";
    default_material_ = std::uint32_t(scene_.materials.size());
    scene_.materials.push_back(fallback);
  }
  return *default_material_;
}

void PrimitiveEmitter::emit_primitive(int mesh, int primitive, const glm::dmat4& world) {
  const tinygltf::Primitive& prim = m_.model.meshes[std::size_t(mesh)].primitives[std::size_t(primitive)];
  const std::string what = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
  const int mode = prim.mode;
  if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
    ++scene_.stats.non_triangle_primitives_skipped;
    if (!warned_non_triangles_)
      print_scene_warnings(m_.file, "skipping point and line primitives (only triangles are rendered)");
    warned_non_triangles_ = true;
    return;
  }
  if (mode < TINYGLTF_MODE_TRIANGLES || mode > TINYGLTF_MODE_TRIANGLE_FAN)
    throw SceneError(m_.file, what + ": unknown primitive mode " + std::to_string(mode));
  const std::uint32_t material = material_id(prim.material, what);

  const bool wants_texcoords1 = scene_.materials[material].uses_texcoord(1);
  const WorldVertices v = world_vertices(m_, prim, world, wants_texcoords1, what);
  if (wants_texcoords1 && v.texcoords1.empty() && !warned_missing_texcoords1_) {
    // GPU viewers read a missing attribute as 0; so does Lancer (kHasTexcoords1 unset).
    print_scene_warnings(m_.file, what + ": its material uses TEXCOORD_1 but the primitive has none");
    warned_missing_texcoords1_ = true;
  }
  const std::vector<std::uint32_t> numbers = vertex_numbers(m_, prim, v.positions.size(), what);
  const std::size_t n = numbers.size();
  std::size_t triangles = 0;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0)
      throw SceneError(m_.file,
                       what + ": TRIANGLES primitive has " + std::to_string(n) + " vertices, not a multiple of 3");
    triangles = n / 3;
  } else {
    triangles = n >= 3 ? n - 2 : 0;
  }

  // glTF 2.0 spec, "Transformations": a node whose matrix has a negative determinant
  // mirrors its meshes, turning counter-clockwise (front) triangles clockwise.
  // Swapping two corners restores cross(b - a, c - a) to the front side.
  const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
  builder_.reserve_more(triangles);  // counted from indices already read and checked
  for (std::size_t t = 0; t < triangles; ++t) {
    std::array<std::size_t, 3> c = triangle_corners(mode, t);
    if (mirrored) std::swap(c[1], c[2]);
    glm::vec3 p[3], nrm[3];
    glm::vec2 uv[3], uv1[3];
    glm::vec4 tan[3], color[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t vtx = numbers[c[std::size_t(k)]];
      p[k] = v.positions[vtx];
      if (!v.normals.empty()) nrm[k] = v.normals[vtx];
      if (!v.texcoords.empty()) uv[k] = v.texcoords[vtx];
      if (!v.texcoords1.empty()) uv1[k] = v.texcoords1[vtx];
      if (!v.tangents.empty()) tan[k] = v.tangents[vtx];
      if (!v.colors.empty()) color[k] = v.colors[vtx];
    }
    CornerAttributes attribs;
    if (!v.normals.empty()) attribs.normals = nrm;
    if (!v.texcoords.empty()) attribs.texcoords = uv;
    if (!v.tangents.empty()) attribs.tangents = tan;
    if (!v.texcoords1.empty()) attribs.texcoords1 = uv1;
    if (!v.colors.empty()) attribs.colors = color;
    if (next_source_id_ == UINT32_MAX) throw SceneError(m_.file, "too many triangles: source ids are 32-bit");
    builder_.add_triangle(p, material, next_source_id_++, attribs);
  }
}

}  // namespace lancer::gltf
