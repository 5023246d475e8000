#include "scene/gltf_primitives.h"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vector_relational.hpp>
#include <type_traits>
#include <utility>

#include "scene/gltf_draco.h"
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
  std::vector<char> mirrored;        // skinned: whether each vertex's matrix mirrors; else empty
};

int attribute(const tinygltf::Primitive& p, const char* name) {
  const auto it = p.attributes.find(name);
  return it == p.attributes.end() ? -1 : it->second;
}

// Adds the primitive's morph targets, weighted (glTF 2.0, "Morph Targets"): POSITION,
// NORMAL and TANGENT (xyz) displacements; the builder normalises the normals.
void apply_morph_targets(const ModelRef& m, const tinygltf::Primitive& prim, const std::vector<double>& weights,
                         WorldVertices& v, const std::string& what) {
  if (prim.targets.size() != weights.size())
    throw SceneError(m.file, what + " has " + std::to_string(prim.targets.size()) + " morph targets but " +
                                 std::to_string(weights.size()) + " weights are given");
  const std::size_t n = v.positions.size();
  for (std::size_t t = 0; t < prim.targets.size(); ++t) {
    const float w = float(weights[t]);
    if (w == 0.0f) continue;
    const std::string target = what + " target " + std::to_string(t);
    for (const auto& [name, accessor] : prim.targets[t]) {
      std::vector<glm::vec3> delta;
      if (name == "POSITION")
        delta = read_positions(m, accessor, target + " POSITION");
      else if (name == "NORMAL" || name == "TANGENT")
        delta = read_normals(m, accessor, target + " " + name);
      else
        continue;  // TEXCOORD_n / COLOR_n targets: not applied
      if (delta.size() != n)
        throw SceneError(m.file, target + " " + name + " has " + std::to_string(delta.size()) +
                                     " elements but POSITION has " + std::to_string(n));
      if (name == "POSITION")
        for (std::size_t k = 0; k < n; ++k) v.positions[k] += w * delta[k];
      else if (name == "NORMAL")
        for (std::size_t k = 0; k < v.normals.size(); ++k) v.normals[k] += w * delta[k];
      else
        for (std::size_t k = 0; k < v.tangents.size(); ++k) v.tangents[k] += glm::vec4(w * delta[k], 0.0f);
    }
  }
}

// The cofactor matrix of L times sign(det L): L^-T up to a positive factor, defined
// even where L is singular (the builder normalises what it transforms).
glm::dmat3 normal_matrix(const glm::dmat3& linear) {
  const double sign = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
  return sign * glm::dmat3(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                           glm::cross(linear[0], linear[1]));
}

// Linear blend skinning (glTF 2.0, "Skins"): each vertex moves by the sum of its joints'
// matrices weighted by WEIGHTS_n (JOINTS_0 / WEIGHTS_0 and, when present, _1), the
// weights divided by their sum; normals by that matrix's normal_matrix, tangents by its
// linear part. The result is in world space.
void apply_skin(const ModelRef& m, const tinygltf::Primitive& prim, const DracoPrimitive* draco,
                const std::vector<glm::dmat4>& joints, WorldVertices& v, const std::string& what) {
  const std::size_t n = v.positions.size();
  std::vector<std::vector<glm::uvec4>> joint_sets;
  std::vector<std::vector<glm::vec4>> weight_sets;
  for (int set = 0;; ++set) {
    const std::string j_name = "JOINTS_" + std::to_string(set), w_name = "WEIGHTS_" + std::to_string(set);
    const int j = attribute(prim, j_name.c_str()), w = attribute(prim, w_name.c_str());
    if (j < 0 && w < 0) break;
    if (j < 0 || w < 0)
      throw SceneError(m.file, what + " has " + (j < 0 ? w_name : j_name) + " without " + (j < 0 ? j_name : w_name));
    // From the Draco data where it holds them, else from the accessors.
    const std::vector<glm::vec4>* draco_joints = draco ? draco->find(j_name) : nullptr;
    const std::vector<glm::vec4>* draco_weights = draco ? draco->find(w_name) : nullptr;
    joint_sets.push_back(draco_joints ? std::vector<glm::uvec4>{} : read_joints(m, j, what + " " + j_name));
    weight_sets.push_back(draco_weights ? *draco_weights : read_weights(m, w, what + " " + w_name));
    if (const std::vector<glm::vec4>* d = draco_joints) {
      joint_sets.back().assign(d->size(), glm::uvec4(0));
      for (std::size_t k = 0; k < d->size(); ++k) {
        const glm::vec4 index = (*d)[k];
        if (!(glm::all(glm::greaterThanEqual(index, glm::vec4(0.0f))) &&
              glm::all(glm::lessThanEqual(index, glm::vec4(65535.0f)))))
          throw SceneError(m.file, what + " " + j_name + " (Draco) holds a joint index outside 0..65535");
        joint_sets.back()[k] = glm::uvec4(index);
      }
    }
    if (joint_sets.back().size() != n || weight_sets.back().size() != n)
      throw SceneError(m.file, what + " " + j_name + " or " + w_name + " does not have one element per vertex (" +
                                   std::to_string(n) + ")");
  }
  if (joint_sets.empty()) throw SceneError(m.file, what + " belongs to a skinned node but has no JOINTS_0 / WEIGHTS_0");
  v.mirrored.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    glm::dmat4 blend(0.0);
    double total = 0.0;
    for (std::size_t s = 0; s < joint_sets.size(); ++s)
      for (int c = 0; c < 4; ++c) {
        const double w = weight_sets[s][k][c];
        if (!(w >= 0.0) || !std::isfinite(w))
          throw SceneError(m.file, what + " vertex " + std::to_string(k) + " has a negative or non-finite joint weight");
        if (w == 0.0) continue;
        const unsigned joint = joint_sets[s][k][c];
        if (joint >= joints.size())
          throw SceneError(m.file, what + " vertex " + std::to_string(k) + ": joint " + std::to_string(joint) +
                                       " out of range (the skin has " + std::to_string(joints.size()) + " joints)");
        blend += w * joints[joint];
        total += w;
      }
    if (!(total > 0.0))
      throw SceneError(m.file, what + " vertex " + std::to_string(k) + " has no joint weight");
    blend /= total;
    const glm::dmat3 linear(blend);
    v.positions[k] = glm::vec3(blend * glm::dvec4(v.positions[k], 1.0));
    if (k < v.normals.size()) v.normals[k] = glm::vec3(normal_matrix(linear) * glm::dvec3(v.normals[k]));
    const bool mirrored = glm::determinant(linear) < 0.0;
    if (k < v.tangents.size()) {
      glm::dvec3 xyz = linear * glm::dvec3(v.tangents[k]);
      const double len = glm::length(xyz);
      if (len > 0.0) xyz /= len;
      v.tangents[k] = glm::vec4(glm::vec3(xyz), mirrored ? -v.tangents[k].w : v.tangents[k].w);
    }
    v.mirrored[k] = mirrored ? 1 : 0;
  }
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
WorldVertices world_vertices(const ModelRef& m, const tinygltf::Primitive& prim, const DracoPrimitive* draco,
                             const glm::dmat4& world, const MeshPose& pose, bool want_texcoords1,
                             const std::string& what) {
  WorldVertices v;
  // Each attribute from the Draco data when it is compressed there, else from its accessor.
  auto read = [&](const char* semantic, auto& out, auto read_accessor) {
    const int a = attribute(prim, semantic);
    const std::vector<glm::vec4>* decoded = draco ? draco->find(semantic) : nullptr;
    if (decoded) {
      using Vec = typename std::remove_reference_t<decltype(out)>::value_type;
      out.resize(decoded->size());
      for (std::size_t k = 0; k < decoded->size(); ++k) out[k] = Vec((*decoded)[k]);
    } else if (a >= 0) {
      out = read_accessor(m, a, what + " " + semantic);
    }
    return decoded != nullptr || a >= 0;
  };
  if (!read("POSITION", v.positions, read_positions)) throw SceneError(m.file, what + " has no POSITION attribute");
  const std::size_t n = v.positions.size();
  if (draco && n != draco->points)
    throw SceneError(m.file, what + " POSITION has " + std::to_string(n) + " elements but its Draco data " +
                                 std::to_string(draco->points) + " points");
  auto check_count = [&](std::size_t count, const char* name) {
    if (count != n)
      throw SceneError(m.file, what + " " + name + " has " + std::to_string(count) + " elements but POSITION has " +
                                   std::to_string(n));
  };
  if (read("NORMAL", v.normals, read_normals)) check_count(v.normals.size(), "NORMAL");
  if (read("TEXCOORD_0", v.texcoords, read_texcoords)) check_count(v.texcoords.size(), "TEXCOORD_0");
  if (want_texcoords1 && read("TEXCOORD_1", v.texcoords1, read_texcoords))
    check_count(v.texcoords1.size(), "TEXCOORD_1");
  if (read("COLOR_0", v.colors, read_colors)) {
    check_count(v.colors.size(), "COLOR_0");
    for (glm::vec4& c : v.colors) c = glm::clamp(c, glm::vec4(0.0f), glm::vec4(1.0f));
  }
  if (!v.normals.empty() && read("TANGENT", v.tangents, read_tangents)) check_count(v.tangents.size(), "TANGENT");

  if (!pose.morph_weights.empty()) apply_morph_targets(m, prim, pose.morph_weights, v, what);
  if (!pose.joints.empty()) {
    apply_skin(m, prim, draco, pose.joints, v, what);
    return v;
  }
  const glm::dmat3 linear(world);
  const double sign = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
  const glm::dmat3 normals = normal_matrix(linear);
  for (glm::vec3& p : v.positions) p = glm::vec3(world * glm::dvec4(p, 1.0));
  for (glm::vec3& nrm : v.normals) nrm = glm::vec3(normals * glm::dvec3(nrm));
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
std::vector<std::uint32_t> vertex_numbers(const ModelRef& m, const tinygltf::Primitive& prim, const DracoPrimitive* draco,
                                          std::size_t vertex_count, const std::string& what) {
  if (draco) return draco->indices;  // checked against its point count, which is vertex_count
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

void PrimitiveEmitter::emit_mesh(int mesh, const glm::dmat4& world, const MeshPose& pose) {
  if (mesh < 0 || std::size_t(mesh) >= m_.model.meshes.size())
    throw SceneError(m_.file, "mesh index " + std::to_string(mesh) + " out of range (the file has " +
                                  std::to_string(m_.model.meshes.size()) + " meshes)");
  const std::size_t count = m_.model.meshes[std::size_t(mesh)].primitives.size();
  for (std::size_t p = 0; p < count; ++p) emit_primitive(mesh, int(p), world, pose);
}

const DracoPrimitive* PrimitiveEmitter::draco(int mesh, int primitive, const std::string& what) {
  auto [it, added] = draco_.try_emplace({mesh, primitive});
  if (added)
    it->second = decode_draco(m_, m_.model.meshes[std::size_t(mesh)].primitives[std::size_t(primitive)], what);
  return it->second ? &*it->second : nullptr;
}

std::size_t PrimitiveEmitter::triangle_bound(int mesh) {
  if (mesh < 0 || std::size_t(mesh) >= m_.model.meshes.size()) return 0;
  const auto& accessors = m_.model.accessors;
  std::size_t bound = 0;
  const auto& primitives = m_.model.meshes[std::size_t(mesh)].primitives;
  for (std::size_t p = 0; p < primitives.size(); ++p) {
    const tinygltf::Primitive& prim = primitives[p];
    // A Draco primitive's faces are known only decoded (its "indices" was dropped, and its
    // points say nothing of how many faces use them).
    const std::string what = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(p);
    if (const DracoPrimitive* d = draco(mesh, int(p), what)) {
      bound += d->indices.size() / 3;
      continue;
    }
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

void PrimitiveEmitter::emit_primitive(int mesh, int primitive, const glm::dmat4& world, const MeshPose& pose) {
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
  const DracoPrimitive* compressed = draco(mesh, primitive, what);
  const WorldVertices v = world_vertices(m_, prim, compressed, world, pose, wants_texcoords1, what);
  if (wants_texcoords1 && v.texcoords1.empty() && !warned_missing_texcoords1_) {
    // GPU viewers read a missing attribute as 0; so does Lancer (kHasTexcoords1 unset).
    print_scene_warnings(m_.file, what + ": its material uses TEXCOORD_1 but the primitive has none");
    warned_missing_texcoords1_ = true;
  }
  const std::vector<std::uint32_t> numbers = vertex_numbers(m_, prim, compressed, v.positions.size(), what);
  const std::size_t n = numbers.size();
  // Draco hands back triangles whatever the primitive's mode (TRIANGLES or a strip).
  const int layout = compressed ? TINYGLTF_MODE_TRIANGLES : mode;
  std::size_t triangles = 0;
  if (layout == TINYGLTF_MODE_TRIANGLES) {
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
  // A skinned vertex has its own matrix: the triangle follows its first corner's.
  const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
  builder_.reserve_more(triangles);  // counted from indices already read and checked
  for (std::size_t t = 0; t < triangles; ++t) {
    std::array<std::size_t, 3> c = triangle_corners(layout, t);
    if (v.mirrored.empty() ? mirrored : v.mirrored[numbers[c[0]]] != 0) std::swap(c[1], c[2]);
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
