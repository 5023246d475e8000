// Wavefront OBJ + MTL. The text first goes through a strict pass (obj_text_check.h)
// that refuses what tinyobjloader would read silently wrong; tinyobjloader then parses
// it with triangulate = false, and each polygon is fan-triangulated here in file order,
// (v0, vi, vi+1), so a triangle's source id is its position among the file's triangles,
// counting the degenerate ones SceneBuilder drops.
#include "scene/obj_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <tiny_obj_loader.h>

#include "scene/obj_material.h"
#include "scene/obj_text_check.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer {

namespace {

namespace fs = std::filesystem;

// Opens each `mtllib` relative to the OBJ's folder (tinyobjloader's own reader splits
// its search path at ':', which breaks on such folder names) and remembers the folder
// each material came from, so its textures resolve relative to its own MTL file.
class MtlLibraryReader final : public tinyobj::MaterialReader {
 public:
  explicit MtlLibraryReader(fs::path obj_dir) : obj_dir_(std::move(obj_dir)) {}

  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* index_by_name, std::string* warn, std::string* err) override {
    const fs::path path = obj_dir_ / fs::path(name);
    std::error_code ec;
    std::ifstream in;
    if (fs::is_regular_file(path, ec)) in.open(path, std::ios::binary);
    if (!in.is_open()) {
      if (warn) *warn += "material library '" + path.string() + "' not found\n";
      return false;
    }
    tinyobj::LoadMtl(index_by_name, materials, &in, warn, err);
    material_dirs_.resize(materials->size(), path.parent_path());
    return true;
  }

  const fs::path& material_dir(std::size_t material) const {
    return material < material_dirs_.size() ? material_dirs_[material] : obj_dir_;
  }

 private:
  fs::path obj_dir_;
  std::vector<fs::path> material_dirs_;
};

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n.");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}


std::string read_whole_file(const fs::path& path, const std::string& file) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(file, "cannot be opened");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneError(file, "read error");
  return text;
}

// Turns tinyobjloader's untriangulated shapes into triangles. Indices were range-checked
// by check_obj_text; they are checked again here because an out-of-range read would be
// memory corruption rather than a wrong picture.
class FanTriangulator {
 public:
  FanTriangulator(const tinyobj::attrib_t& attrib, SceneBuilder& builder, std::string file,
                  std::size_t material_count, std::uint32_t default_material)
      : attrib_(attrib),
        builder_(builder),
        file_(std::move(file)),
        material_count_(material_count),
        default_material_(default_material) {}

  void add_shape(const tinyobj::shape_t& shape) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    if (mesh.material_ids.size() != mesh.num_face_vertices.size())
      throw SceneError(file_, "shape '" + shape.name + "': face and material counts disagree");
    // Fanned triangles: at most one per parsed index, so this count is backed by data.
    std::size_t triangles = 0;
    for (unsigned char corners : mesh.num_face_vertices) triangles += corners >= 3 ? corners - 2u : 0u;
    builder_.reserve_more(std::min(triangles, mesh.indices.size()));
    std::size_t offset = 0;
    for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const std::size_t corners = mesh.num_face_vertices[f];
      if (offset + corners > mesh.indices.size())
        throw SceneError(file_, "shape '" + shape.name + "': face " + std::to_string(f) + " runs past its indices");
      const int id = mesh.material_ids[f];
      const std::uint32_t material =
          id >= 0 && static_cast<std::size_t>(id) < material_count_ ? static_cast<std::uint32_t>(id) : default_material_;
      for (std::size_t k = 1; k + 1 < corners; ++k)
        add_triangle(mesh.indices[offset], mesh.indices[offset + k], mesh.indices[offset + k + 1], material);
      offset += corners;
    }
    if (offset != mesh.indices.size())
      throw SceneError(file_, "shape '" + shape.name + "': face sizes do not add up to its index count");
  }

 private:
  void add_triangle(const tinyobj::index_t& a, const tinyobj::index_t& b, const tinyobj::index_t& c,
                    std::uint32_t material) {
    if (next_source_id_ > std::numeric_limits<std::uint32_t>::max())
      throw SceneError(file_, "more than 2^32 triangles");
    const std::uint32_t source_id = static_cast<std::uint32_t>(next_source_id_++);
    const tinyobj::index_t* corner[3] = {&a, &b, &c};
    glm::vec3 p[3], n[3];
    glm::vec2 uv[3];
    glm::vec4 rgba[3];
    bool has_normals = true, has_texcoords = true;
    // tinyobjloader keeps the colours ("v x y z r g b") only when every vertex has one.
    const bool has_colors = !attrib_.colors.empty() && attrib_.colors.size() == attrib_.vertices.size();
    for (int k = 0; k < 3; ++k) {
      const std::size_t v = checked(corner[k]->vertex_index, attrib_.vertices.size() / 3, "vertex", source_id);
      p[k] = {attrib_.vertices[3 * v], attrib_.vertices[3 * v + 1], attrib_.vertices[3 * v + 2]};
      if (has_colors)
        rgba[k] = glm::vec4(vertex_color(attrib_.colors[3 * v]), vertex_color(attrib_.colors[3 * v + 1]),
                            vertex_color(attrib_.colors[3 * v + 2]), 1.0f);
      if (corner[k]->normal_index < 0) {
        has_normals = false;
      } else {
        const std::size_t i = checked(corner[k]->normal_index, attrib_.normals.size() / 3, "normal", source_id);
        n[k] = {attrib_.normals[3 * i], attrib_.normals[3 * i + 1], attrib_.normals[3 * i + 2]};
      }
      if (corner[k]->texcoord_index < 0) {
        has_texcoords = false;
      } else {
        const std::size_t i = checked(corner[k]->texcoord_index, attrib_.texcoords.size() / 2, "texcoord", source_id);
        // OBJ puts v = 0 at the bottom of the image, glTF (and Scene) at the top.
        uv[k] = {attrib_.texcoords[2 * i], 1.0f - attrib_.texcoords[2 * i + 1]};
      }
    }
    CornerAttributes attribs;
    attribs.normals = has_normals ? n : nullptr;
    attribs.texcoords = has_texcoords ? uv : nullptr;
    attribs.colors = has_colors ? rgba : nullptr;
    builder_.add_triangle(p, material, source_id, attribs);
  }

  // OBJ's vertex colour extension has no colour space of its own; the files that carry it
  // (scanners, MeshLab) write 8-bit display colours over 255, i.e. sRGB, which is how
  // Blender's importer reads them too. Decoded to linear (IEC 61966-2-1), clamped to
  // [0, 1] as glTF's COLOR_0 is; not a number is an error.
  float vertex_color(float encoded) const {
    if (std::isnan(encoded)) throw SceneError(file_, "a vertex colour is not a number");
    const float c = std::clamp(encoded, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  }

  std::size_t checked(int index, std::size_t count, const char* what, std::uint32_t source_id) const {
    if (index < 0 || static_cast<std::size_t>(index) >= count)
      throw SceneError(file_, "triangle " + std::to_string(source_id) + ": " + what + " index " +
                                  std::to_string(index) + " is out of range (" + std::to_string(count) + ")");
    return static_cast<std::size_t>(index);
  }

  const tinyobj::attrib_t& attrib_;
  SceneBuilder& builder_;
  std::string file_;
  std::size_t material_count_;
  std::uint32_t default_material_;
  std::uint64_t next_source_id_ = 0;
};

}  // namespace

Scene read_obj(const fs::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError(file, "no such file");
  if (!fs::is_regular_file(path, ec)) throw SceneError(file, "not a regular file");

  const std::string text = read_whole_file(path, file);
  const obj_detail::ObjTextSummary summary = obj_detail::check_obj_text(text, file);
  if (summary.unknown_statements > 0)
    print_scene_warnings(file, "ignored " + std::to_string(summary.unknown_statements) +
                             " line(s) with an unknown keyword, the first on line " +
                             std::to_string(summary.first_unknown_line));

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> mtl_materials;
  std::string warnings, errors;
  std::istringstream stream(text);
  MtlLibraryReader mtl_reader(path.parent_path());
  const bool parsed = tinyobj::LoadObj(&attrib, &shapes, &mtl_materials, &warnings, &errors, &stream, &mtl_reader,
                                       /*triangulate=*/false, /*default_vcols_fallback=*/false);
  print_scene_warnings(file, warnings);
  if (!parsed || !trim(errors).empty())
    throw SceneError(file, trim(errors).empty() ? "tinyobjloader could not parse the file" : trim(errors));

  Scene scene;
  scene.source = file;
  scene.stats.non_triangle_primitives_skipped = summary.lines_and_points;
  obj_detail::ObjTextureLoader textures(scene, file);
  for (std::size_t i = 0; i < mtl_materials.size(); ++i)
    scene.materials.push_back(
        obj_detail::convert_mtl_material(mtl_materials[i], mtl_reader.material_dir(i), textures, file));

  // Faces before any `usemtl`, or naming a material no MTL defines, get a default one.
  bool any_without_material = false;
  for (const tinyobj::shape_t& shape : shapes)
    for (int id : shape.mesh.material_ids)
      any_without_material |= id < 0 || static_cast<std::size_t>(id) >= mtl_materials.size();
  const auto default_material = static_cast<std::uint32_t>(scene.materials.size());
  if (any_without_material) scene.materials.push_back(obj_detail::default_obj_material());

  SceneBuilder builder(scene, file);
  FanTriangulator triangulator(attrib, builder, file, mtl_materials.size(), default_material);
  for (const tinyobj::shape_t& shape : shapes) triangulator.add_shape(shape);
  builder.finish();
  return scene;
}

}  // namespace lancer
