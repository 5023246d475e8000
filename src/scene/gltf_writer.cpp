// Binary glTF writer: the Scene is turned into a tinygltf::Model (welded, indexed
// primitives in one embedded buffer) and serialised by tinygltf into a stream we own,
// so every failure is reported (tinygltf's own file writer, WriteGltfSceneToFile, does
// not check that its output file opened or that the writes succeeded).
#include "scene/gltf_writer.h"

#include <fcntl.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "scene/scene_error.h"
#include "simd/splitmix64.h"

namespace lancer {

namespace {

namespace fs = std::filesystem;

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr std::size_t kMaxBufferBytes = std::size_t(UINT32_MAX) - (std::size_t(256) << 20);

std::uint32_t bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Consecutive triangles with one material and one normals flag: one glTF primitive.
struct Run {
  std::size_t first = 0;
  std::size_t count = 0;
  std::uint32_t material = 0;
  bool normals = false;
};

bool has_normals(const Scene& scene, std::size_t t) { return (scene.attrib_flags[t] & kHasNormals) != 0; }

std::vector<Run> runs_of(const Scene& scene) {
  std::vector<Run> runs;
  for (std::size_t t = 0; t < scene.triangle_count(); ++t) {
    const std::uint32_t m = scene.material_id[t];
    const bool n = has_normals(scene, t);
    if (runs.empty() || runs.back().material != m || runs.back().normals != n) runs.push_back({t, 0, m, n});
    ++runs.back().count;
  }
  return runs;
}

// Welds corners with identical bits into one vertex: an open-addressing hash table of
// vertex numbers (linear probing, kept at most half full).
class VertexWelder {
 public:
  VertexWelder(bool with_normals, std::size_t corners) : with_normals_(with_normals) {
    std::size_t capacity = 1024;
    while (capacity < corners / 2) capacity *= 2;  // closed meshes have about corners / 6 vertices
    slots_.assign(capacity, 0);
  }

  std::uint32_t index_of(const glm::vec3& p, const glm::vec3& n) {
    if (2 * (positions_.size() + 1) > slots_.size()) grow();
    std::size_t slot = hash(p, n) & (slots_.size() - 1);
    while (slots_[slot] != 0) {
      const std::uint32_t v = slots_[slot] - 1;
      if (same(positions_[v], p) && (!with_normals_ || same(normals_[v], n))) return v;
      slot = (slot + 1) & (slots_.size() - 1);
    }
    if (positions_.size() >= std::size_t(UINT32_MAX - 1)) throw std::length_error("more than 2^32 - 2 vertices");
    positions_.push_back(p);
    if (with_normals_) normals_.push_back(n);
    slots_[slot] = static_cast<std::uint32_t>(positions_.size());
    return static_cast<std::uint32_t>(positions_.size() - 1);
  }

  std::vector<glm::vec3> take_positions() { return std::move(positions_); }
  std::vector<glm::vec3> take_normals() { return std::move(normals_); }

 private:
  static bool same(const glm::vec3& a, const glm::vec3& b) {
    return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z);
  }
  std::uint64_t hash(const glm::vec3& p, const glm::vec3& n) const {
    std::uint64_t h = splitmix64_mix(std::uint64_t(bits(p.x)) << 32 | bits(p.y));
    h = splitmix64_mix(h ^ bits(p.z));
    if (with_normals_) {
      h = splitmix64_mix(h ^ (std::uint64_t(bits(n.x)) << 32 | bits(n.y)));
      h = splitmix64_mix(h ^ bits(n.z));
    }
    return h;
  }
  void grow() {
    std::vector<std::uint32_t> old(slots_.size() * 2, 0);
    old.swap(slots_);
    for (std::uint32_t entry : old) {
      if (entry == 0) continue;
      const std::uint32_t v = entry - 1;
      std::size_t slot = hash(positions_[v], with_normals_ ? normals_[v] : glm::vec3(0.0f)) & (slots_.size() - 1);
      while (slots_[slot] != 0) slot = (slot + 1) & (slots_.size() - 1);
      slots_[slot] = entry;
    }
  }

  bool with_normals_;
  std::vector<std::uint32_t> slots_;  // 0: empty, else vertex number + 1
  std::vector<glm::vec3> positions_;
  std::vector<glm::vec3> normals_;
};

// One run welded into indexed vertices.
struct WeldedRun {
  Run run;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty without normals
  std::vector<std::uint32_t> indices;
  std::size_t bytes() const {
    return (positions.size() + normals.size()) * sizeof(glm::vec3) + indices.size() * sizeof(std::uint32_t);
  }
};

WeldedRun weld(const Scene& scene, const Run& run) {
  VertexWelder welder(run.normals, 3 * run.count);
  WeldedRun w;
  w.run = run;
  w.indices.reserve(3 * run.count);
  for (std::size_t t = run.first; t < run.first + run.count; ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = run.normals ? scene.normals[3 * t + std::size_t(k)] : glm::vec3(0.0f);
      w.indices.push_back(welder.index_of(scene.triangles.vertex(t, k), n));
    }
  w.positions = welder.take_positions();
  w.normals = welder.take_normals();
  return w;
}

// Appends `size` bytes to buffer 0 (reserved by the caller) as a new buffer view and
// returns an accessor over it.
int add_accessor(tinygltf::Model& model, const void* data, std::size_t size, int target, int component_type, int type,
                 std::size_t count) {
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();  // every element here is 4-byte aligned
  view.byteLength = size;
  view.target = target;
  const auto* first = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), first, first + size);
  model.bufferViews.push_back(view);

  tinygltf::Accessor accessor;
  accessor.bufferView = int(model.bufferViews.size() - 1);
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(accessor);
  return int(model.accessors.size() - 1);
}

tinygltf::Primitive add_primitive(tinygltf::Model& model, const WeldedRun& w) {
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = int(w.run.material);
  const int position = add_accessor(model, w.positions.data(), w.positions.size() * sizeof(glm::vec3),
                                    TINYGLTF_TARGET_ARRAY_BUFFER, kFloat, TINYGLTF_TYPE_VEC3, w.positions.size());
  // glTF 2.0 spec, "Accessors": POSITION must give its min and max.
  glm::vec3 lo = w.positions[0], hi = w.positions[0];
  for (const glm::vec3& p : w.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  model.accessors[std::size_t(position)].minValues = {lo.x, lo.y, lo.z};
  model.accessors[std::size_t(position)].maxValues = {hi.x, hi.y, hi.z};
  prim.attributes["POSITION"] = position;
  if (w.run.normals)
    prim.attributes["NORMAL"] =
        add_accessor(model, w.normals.data(), w.normals.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER,
                     kFloat, TINYGLTF_TYPE_VEC3, w.normals.size());
  prim.indices =
      add_accessor(model, w.indices.data(), w.indices.size() * sizeof(std::uint32_t),
                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, kUnsignedInt, TINYGLTF_TYPE_SCALAR, w.indices.size());
  return prim;
}

tinygltf::Value object_value(const char* key, tinygltf::Value value) {
  tinygltf::Value::Object o;
  o[key] = std::move(value);
  return tinygltf::Value(std::move(o));
}

void add_extension(tinygltf::Model& model, const std::string& name) {
  for (const std::string& used : model.extensionsUsed)
    if (used == name) return;
  model.extensionsUsed.push_back(name);
}

void add_materials(tinygltf::Model& model, const Scene& scene, const std::string& file) {
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    if (m.base_color_texture.present() || m.metallic_roughness_texture.present() || m.emissive_texture.present() ||
        m.normal_texture.present() || m.occlusion_texture.present())
      throw SceneError(file, "material " + std::to_string(i) + " ('" + m.name +
                                 "') uses textures, which the glTF writer does not write");
    tinygltf::Material g;
    g.name = m.name;
    g.pbrMetallicRoughness.baseColorFactor = {m.base_color.r, m.base_color.g, m.base_color.b, m.base_color.a};
    g.pbrMetallicRoughness.metallicFactor = m.metallic;
    g.pbrMetallicRoughness.roughnessFactor = m.roughness;
    g.emissiveFactor = {m.emissive_factor.r, m.emissive_factor.g, m.emissive_factor.b};
    g.alphaMode = m.alpha_mode == AlphaMode::Mask ? "MASK" : m.alpha_mode == AlphaMode::Blend ? "BLEND" : "OPAQUE";
    g.alphaCutoff = m.alpha_cutoff;
    g.doubleSided = m.double_sided;
    const auto extend = [&](const char* name, tinygltf::Value value) {
      g.extensions[name] = std::move(value);
      add_extension(model, name);
    };
    if (m.emissive_strength != 1.0f)
      extend("KHR_materials_emissive_strength",
             object_value("emissiveStrength", tinygltf::Value(double(m.emissive_strength))));
    if (m.ior != 1.5f) extend("KHR_materials_ior", object_value("ior", tinygltf::Value(double(m.ior))));
    if (m.transmission != 0.0f)
      extend("KHR_materials_transmission", object_value("transmissionFactor", tinygltf::Value(double(m.transmission))));
    // KHR_materials_volume: without it a transmissive surface is a thin wall on reading.
    if (m.thickness != 0.0f || std::isfinite(m.attenuation_distance) || m.attenuation_color != glm::vec3(1.0f)) {
      tinygltf::Value::Object o;
      o["thicknessFactor"] = tinygltf::Value(double(m.thickness));
      if (std::isfinite(m.attenuation_distance))
        o["attenuationDistance"] = tinygltf::Value(double(m.attenuation_distance));
      o["attenuationColor"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(m.attenuation_color.r)),
                                                                     tinygltf::Value(double(m.attenuation_color.g)),
                                                                     tinygltf::Value(double(m.attenuation_color.b))});
      extend("KHR_materials_volume", tinygltf::Value(std::move(o)));
    }
    if (m.specular != 1.0f || m.specular_color != glm::vec3(1.0f)) {
      tinygltf::Value::Object o;
      o["specularFactor"] = tinygltf::Value(double(m.specular));
      o["specularColorFactor"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(m.specular_color.r)),
                                                                        tinygltf::Value(double(m.specular_color.g)),
                                                                        tinygltf::Value(double(m.specular_color.b))});
      extend("KHR_materials_specular", tinygltf::Value(std::move(o)));
    }
    if (m.clearcoat != 0.0f || m.clearcoat_roughness != 0.0f) {
      tinygltf::Value::Object o;
      o["clearcoatFactor"] = tinygltf::Value(double(m.clearcoat));
      o["clearcoatRoughnessFactor"] = tinygltf::Value(double(m.clearcoat_roughness));
      extend("KHR_materials_clearcoat", tinygltf::Value(std::move(o)));
    }
    if (m.sheen_color != glm::vec3(0.0f) || m.sheen_roughness != 0.0f) {
      tinygltf::Value::Object o;
      o["sheenColorFactor"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(m.sheen_color.r)),
                                                                     tinygltf::Value(double(m.sheen_color.g)),
                                                                     tinygltf::Value(double(m.sheen_color.b))});
      o["sheenRoughnessFactor"] = tinygltf::Value(double(m.sheen_roughness));
      extend("KHR_materials_sheen", tinygltf::Value(std::move(o)));
    }
    if (m.unlit) extend("KHR_materials_unlit", tinygltf::Value(tinygltf::Value::Object{}));
    model.materials.push_back(std::move(g));
  }
}

std::vector<double> matrix_values(const glm::mat4& m) {
  const float* p = glm::value_ptr(m);  // column-major, as glTF stores node matrices
  return std::vector<double>(p, p + 16);
}

int add_node(tinygltf::Model& model, tinygltf::Node node) {
  model.nodes.push_back(std::move(node));
  return int(model.nodes.size() - 1);
}

void add_cameras(tinygltf::Model& model, const Scene& scene) {
  for (const CameraDesc& desc : scene.cameras) {
    tinygltf::Camera c;
    c.name = desc.name;
    // tinygltf always writes zfar; Lancer traces rays and ignores both planes.
    if (desc.orthographic) {
      c.type = "orthographic";
      c.orthographic.xmag = desc.xmag;
      c.orthographic.ymag = desc.ymag;
      c.orthographic.znear = 0.0;
      c.orthographic.zfar = 1e9;
    } else {
      c.type = "perspective";
      c.perspective.yfov = desc.yfov;
      c.perspective.aspectRatio = desc.aspect_ratio ? double(*desc.aspect_ratio) : 0.0;  // 0: not written
      c.perspective.znear = 1e-3;
      c.perspective.zfar = 1e9;
    }
    model.cameras.push_back(c);
    tinygltf::Node node;
    node.name = desc.name;
    node.camera = int(model.cameras.size() - 1);
    node.matrix = matrix_values(desc.camera_to_world);
    model.scenes[0].nodes.push_back(add_node(model, std::move(node)));
  }
}

// A rigid transform placing the origin at `position` with -z along `direction`.
glm::mat4 light_frame(const glm::vec3& position, const glm::vec3& direction) {
  const glm::dvec3 z = -glm::normalize(glm::dvec3(direction));
  const glm::dvec3 helper = std::abs(z.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0.0, 0.0);
  const glm::dvec3 x = glm::normalize(glm::cross(helper, z));
  const glm::dvec3 y = glm::cross(z, x);
  return glm::mat4(glm::vec4(glm::vec3(x), 0.0f), glm::vec4(glm::vec3(y), 0.0f), glm::vec4(glm::vec3(z), 0.0f),
                   glm::vec4(position, 1.0f));
}

void add_lights(tinygltf::Model& model, const Scene& scene, const std::string& file) {
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const PunctualLight& l = scene.lights[i];
    const float len = glm::length(l.direction);
    if (!(len > 0.0f) || !std::isfinite(len))
      throw SceneError(file, "light " + std::to_string(i) + " has no direction");
    tinygltf::Light g;
    g.name = l.name;
    g.type = l.type == LightType::Spot ? "spot" : l.type == LightType::Directional ? "directional" : "point";
    g.color = {l.color.r, l.color.g, l.color.b};
    g.intensity = l.intensity;
    g.range = l.range;
    g.spot.innerConeAngle = l.inner_cone;
    g.spot.outerConeAngle = l.outer_cone;
    model.lights.push_back(g);
    tinygltf::Node node;
    node.name = l.name;
    node.matrix = matrix_values(light_frame(l.position, l.direction));
    node.extensions["KHR_lights_punctual"] = object_value("light", tinygltf::Value(int(model.lights.size() - 1)));
    model.scenes[0].nodes.push_back(add_node(model, std::move(node)));
  }
}

tinygltf::Model make_model(const Scene& scene, const std::string& file) {
  const std::size_t n = scene.triangle_count();
  if (n == 0) throw SceneError(file, "the scene has no triangles to write");
  if (scene.material_id.size() != n || scene.attrib_flags.size() != n ||
      (!scene.normals.empty() && scene.normals.size() != 3 * n))
    throw SceneError(file, "inconsistent scene: per-triangle arrays do not match the triangle count");
  if (scene.normals.empty())
    for (std::size_t t = 0; t < n; ++t)
      if (has_normals(scene, t)) throw SceneError(file, "inconsistent scene: triangles flagged with normals, none stored");
  for (std::uint32_t id : scene.material_id)
    if (id >= scene.materials.size()) throw SceneError(file, "material index " + std::to_string(id) + " out of range");

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Lancer";
  model.buffers.emplace_back();
  model.scenes.emplace_back();
  model.defaultScene = 0;
  add_materials(model, scene, file);

  // Weld every run first, so the buffer is allocated once at its final size.
  std::vector<WeldedRun> welded;
  std::size_t bytes = 0;
  for (const Run& run : runs_of(scene)) {
    welded.push_back(weld(scene, run));
    bytes += welded.back().bytes();
    // The GLB header stores the file length in 32 bits (glTF 2.0 spec, "Binary glTF
    // Layout"); leave room for the JSON chunk.
    if (bytes > kMaxBufferBytes)
      throw SceneError(file, "the scene needs more than " + std::to_string(kMaxBufferBytes) +
                                 " bytes of buffer data, more than a .glb file can hold");
  }
  model.buffers[0].data.reserve(bytes);
  tinygltf::Mesh mesh;
  mesh.name = scene.source;
  for (WeldedRun& w : welded) {
    mesh.primitives.push_back(add_primitive(model, w));
    w = WeldedRun{};  // release as we go
  }
  model.meshes.push_back(std::move(mesh));
  tinygltf::Node mesh_node;
  mesh_node.name = scene.source;
  mesh_node.mesh = 0;
  model.scenes[0].nodes.push_back(add_node(model, std::move(mesh_node)));
  add_cameras(model, scene);
  add_lights(model, scene, file);
  return model;
}

std::string os_error(int err) { return std::generic_category().message(err); }

// Serialises `model` into "<path>.tmp", flushes it to disk, then renames it over
// `path`: readers see the old file or the whole new one, never a part. The GLB goes
// straight to the file (no copy of it in memory); stream errors are checked here, as
// tinygltf's own file writer checks none.
void write_atomically(const tinygltf::Model& model, const fs::path& path, const std::string& file) {
  fs::path temporary = path;
  temporary += ".tmp";
  const auto fail = [&](const std::string& what) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw SceneError(file, what);
  };
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  if (!out) throw SceneError(file, "cannot create '" + temporary.string() + "': " + os_error(errno));
  errno = 0;
  tinygltf::TinyGLTF writer;
  const bool serialised = writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/false, /*writeBinary=*/true);
  out.flush();
  const std::streamoff size = out ? std::streamoff(out.tellp()) : std::streamoff(-1);
  const int write_errno = errno;
  out.close();
  if (!serialised) fail("tinygltf could not serialise the scene");
  if (size < 0 || !out)
    fail("write to '" + temporary.string() + "' failed: " + (write_errno ? os_error(write_errno) : "I/O error"));
  if (std::uintmax_t(size) > UINT32_MAX)
    fail("the file would be " + std::to_string(size) + " bytes, more than the 4 GiB a .glb header can describe");
  // Flush the data to the disk before the rename makes it visible.
  const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail("cannot reopen '" + temporary.string() + "': " + os_error(errno));
  const int synced = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  if (synced != 0) fail("fsync of '" + temporary.string() + "' failed: " + os_error(sync_errno));
  if (::rename(temporary.c_str(), path.c_str()) != 0)
    fail("cannot rename '" + temporary.string() + "' to the output: " + os_error(errno));
}

}  // namespace

void write_glb(const Scene& scene, const fs::path& path) {
  const std::string file = path.string();
  const fs::path parent = path.parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw SceneError(file, "cannot write: directory '" + parent.string() + "' does not exist");
  write_atomically(make_model(scene, file), path, file);
}

}  // namespace lancer
