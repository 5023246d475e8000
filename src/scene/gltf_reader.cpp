// glTF 2.0 reader. The file is read here, its JSON checked (gltf_json_checks), parsed
// by tinygltf, then every index, size and offset is checked again on use
// (gltf_accessors, gltf_nodes, gltf_materials) since tinygltf trusts most of them.
#include "scene/gltf_reader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <system_error>

#include "scene/gltf_animation.h"
#include "scene/gltf_draco.h"
#include "scene/gltf_instancing.h"
#include "scene/gltf_json_checks.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_mesh_sharing.h"
#include "scene/gltf_meshopt.h"
#include "scene/gltf_nodes.h"
#include "scene/gltf_primitives.h"
#include "scene/gltf_skins.h"
#include "scene/gltf_webp.h"
#include "scene/scene_builder.h"
#include "scene/scene_error.h"
#include "scene/scene_instancing.h"
#include "scene/scene_warning.h"

namespace lancer {

namespace {

using gltf::ModelRef;

std::vector<unsigned char> read_whole_file(const std::filesystem::path& path, const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw SceneError(file, "no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw SceneError(file, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(file, "cannot open file for reading");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneError(file, "read error");
  return bytes;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ';';
  return s;
}

// tinygltf image callback: keep the encoded bytes and decode later with our own
// checks. For images in a bufferView tinygltf passes a pointer it has not
// bounds-checked, so those bytes are not touched here.
bool keep_encoded_image(tinygltf::Image* image, const int /*index*/, std::string* /*err*/, std::string* /*warn*/,
                        int /*req_width*/, int /*req_height*/, const unsigned char* bytes, int size, void* /*user*/) {
  image->as_is = true;
  if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

// tinygltf's own file callbacks open whatever a URI names: a directory then reads as a
// file of 2^63 bytes (std::bad_alloc) and a FIFO blocks fopen forever. External buffers
// and images must be regular files.
bool regular_file_exists(const std::string& path, void* /*user*/) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* /*user*/) {
  auto fail = [&](const std::string& why) {
    if (err) *err += why + ": " + path + "\n";
    return false;
  };
  if (!regular_file_exists(path, nullptr)) return fail("not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot open file for reading");
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) return fail("read error");
  if (out->empty()) return fail("empty file");
  return true;
}

// A GLB's bytes with its JSON chunk replaced by `json` (padded with spaces to 4 bytes, as
// the GLB format asks); the chunks after it are kept. `bytes` passed glb_json_chunk.
std::vector<unsigned char> glb_with_json(std::span<const unsigned char> bytes, const std::string& json,
                                         const std::string& file) {
  auto u32 = [&](std::size_t at) {
    return std::uint32_t(bytes[at]) | std::uint32_t(bytes[at + 1]) << 8 | std::uint32_t(bytes[at + 2]) << 16 |
           std::uint32_t(bytes[at + 3]) << 24;
  };
  const std::size_t total = u32(8), rest = 20 + std::size_t(u32(12));
  std::string padded = json;
  while (padded.size() % 4 != 0) padded += ' ';
  // The rewritten JSON may be longer than the file's (numbers are written out again).
  if (padded.size() + (total - rest) + 20 > std::size_t(UINT32_MAX))
    throw SceneError(file, "binary glTF too large once its JSON is rewritten for tinygltf");
  std::vector<unsigned char> out(bytes.begin(), bytes.begin() + 12);
  auto put32 = [&](std::size_t value) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(value >> (8 * k)));
  };
  put32(padded.size());
  out.insert(out.end(), bytes.begin() + 16, bytes.begin() + 20);  // the chunk type, JSON
  out.insert(out.end(), padded.begin(), padded.end());
  out.insert(out.end(), bytes.begin() + std::ptrdiff_t(rest), bytes.begin() + std::ptrdiff_t(total));
  const std::size_t length = out.size();
  for (int k = 0; k < 4; ++k) out[8 + std::size_t(k)] = static_cast<unsigned char>(length >> (8 * k));
  return out;
}

tinygltf::Model load_model(std::span<const unsigned char> bytes, const std::filesystem::path& path,
                           const std::string& file) {
  if (bytes.empty()) throw SceneError(file, "empty file");
  // tinygltf takes the length as unsigned int.
  if (bytes.size() > std::size_t(UINT_MAX)) throw SceneError(file, "file too large (over 4 GiB)");
  // Binary when the magic says so; a .glb must be binary.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (lower_extension(path) == ".glb" && !binary)
    throw SceneError(file, bytes.size() < 4 ? "truncated binary glTF: shorter than its magic"
                                            : "not a binary glTF file (bad magic, expected 'glTF')");
  const std::string_view json_text = binary
                                         ? gltf::glb_json_chunk(file, bytes)
                                         : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  gltf::check_gltf_json(file, json_text);
  // What tinygltf reads: the file, or a copy whose JSON spares tinygltf parts it cannot
  // take (json_without_draco_indices, plan_meshopt, json_with_webp_data_uris_relabelled).
  std::optional<std::string> changed = gltf::json_without_draco_indices(json_text);
  gltf::MeshoptPlan meshopt = gltf::plan_meshopt(file, changed ? std::string_view(*changed) : json_text);
  if (meshopt.json) changed = std::move(meshopt.json);
  if (std::optional<std::string> webp =
          gltf::json_with_webp_data_uris_relabelled(changed ? std::string_view(*changed) : json_text))
    changed = std::move(webp);
  std::vector<unsigned char> rewritten;
  if (changed) {
    if (binary) {
      rewritten = glb_with_json(bytes, *changed, file);
    } else {
      rewritten.assign(changed->begin(), changed->end());
    }
    bytes = rewritten;
  }

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_encoded_image, nullptr);
  loader.SetFsCallbacks({&regular_file_exists, &tinygltf::ExpandFilePath, &read_regular_file, &tinygltf::WriteWholeFile,
                         nullptr});
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = path.parent_path().string();
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), base_dir)
                : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                             unsigned(bytes.size()), base_dir);
  } catch (const std::exception& e) {
    throw SceneError(file, std::string("invalid glTF: ") + e.what());
  }
  print_scene_warnings(file, warn);  // tinygltf's report, a line each
  // tinygltf also reports some problems in `err` while returning true (a primitive it
  // dropped, a missing required property): those are errors too.
  if (!ok || !err.empty())
    throw SceneError(file, "invalid glTF: " + (err.empty() ? std::string("tinygltf refused the file") : trimmed(err)));
  // Before anything reads an accessor: animation posing does too.
  gltf::decode_meshopt(meshopt.views, model, file);
  return model;
}

// Lancer's thin-lens convention in a camera's extras (scene.h, CameraDesc): a number
// `key`, finite and >= 0 (> 0 unless zero_ok). Absent or non-object extras: nothing.
std::optional<float> camera_extra(const ModelRef& m, const tinygltf::Value& extras, const char* key,
                                  const std::string& what, bool zero_ok) {
  if (!extras.IsObject() || !extras.Has(key)) return std::nullopt;
  const tinygltf::Value& v = extras.Get(key);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
  if (!std::isfinite(x) || x < 0.0 || (x == 0.0 && !zero_ok) || x > double(std::numeric_limits<float>::max()))
    throw SceneError(m.file, what + ": extras." + key + " must be a " + (zero_ok ? "non-negative" : "positive") +
                                 " number (scene units)");
  return float(x);
}

void add_camera(const ModelRef& m, int node, int camera, const glm::dmat4& world, Scene& scene) {
  if (camera < 0 || std::size_t(camera) >= m.model.cameras.size())
    throw SceneError(m.file, "node " + std::to_string(node) + ": camera index " + std::to_string(camera) +
                                 " out of range (the file has " + std::to_string(m.model.cameras.size()) + " cameras)");
  const tinygltf::Camera& c = m.model.cameras[std::size_t(camera)];
  const std::string what = "camera " + std::to_string(camera);
  CameraDesc desc;
  desc.name = !c.name.empty() ? c.name : m.model.nodes[std::size_t(node)].name;
  desc.index = camera;
  desc.camera_to_world = glm::mat4(world);
  if (c.type == "orthographic") {
    // glTF 2.0: xmag and ymag "MUST NOT be equal to zero" and "SHOULD NOT be negative".
    const double xmag = c.orthographic.xmag, ymag = c.orthographic.ymag;
    constexpr double kMax = std::numeric_limits<float>::max();
    if (!(std::abs(xmag) > 0.0 && std::abs(xmag) <= kMax && std::abs(ymag) > 0.0 && std::abs(ymag) <= kMax))
      throw SceneError(m.file, what + ": orthographic xmag and ymag must be finite and non-zero");
    desc.orthographic = true;
    desc.xmag = float(xmag);
    desc.ymag = float(ymag);
    desc.aspect_ratio = float(std::abs(xmag / ymag));
  } else {
    const double yfov = c.perspective.yfov;
    if (!(yfov > 0.0 && yfov < std::numbers::pi))
      throw SceneError(m.file, what + ": yfov must be between 0 and pi radians");
    const double aspect = c.perspective.aspectRatio;  // tinygltf: 0 when absent
    if (!(aspect >= 0.0) || !std::isfinite(aspect)) throw SceneError(m.file, what + ": aspectRatio must be positive");
    desc.yfov = float(yfov);
    if (aspect > 0.0) desc.aspect_ratio = float(aspect);
  }
  desc.aperture_radius = camera_extra(m, c.extras, "aperture", what, true);
  desc.focus_distance = camera_extra(m, c.extras, "focusDistance", what, false);
  scene.cameras.push_back(desc);
}

LightType light_type(const ModelRef& m, const std::string& type, const std::string& what) {
  if (type == "point") return LightType::Point;
  if (type == "spot") return LightType::Spot;
  if (type == "directional") return LightType::Directional;
  throw SceneError(m.file, what + ": unknown KHR_lights_punctual type '" + type + "'");
}

// KHR_lights_punctual: the light sits at the node's origin and shines down its -Z.
void add_light(const ModelRef& m, int node, const glm::dmat4& world, Scene& scene) {
  const auto& extensions = m.model.nodes[std::size_t(node)].extensions;
  const auto ext = extensions.find("KHR_lights_punctual");
  if (ext == extensions.end()) return;
  const std::string node_what = "node " + std::to_string(node) + " KHR_lights_punctual";
  if (!ext->second.IsObject() || !ext->second.Has("light") || !ext->second.Get("light").IsInt())
    throw SceneError(m.file, node_what + " needs an integer 'light'");
  const int index = ext->second.Get("light").GetNumberAsInt();
  if (index < 0 || std::size_t(index) >= m.model.lights.size())
    throw SceneError(m.file, node_what + ": light index " + std::to_string(index) + " out of range (the file has " +
                                 std::to_string(m.model.lights.size()) + " lights)");
  const tinygltf::Light& l = m.model.lights[std::size_t(index)];
  const std::string what = "light " + std::to_string(index);
  PunctualLight out;
  out.name = !l.name.empty() ? l.name : m.model.nodes[std::size_t(node)].name;
  out.type = light_type(m, l.type, what);
  if (!l.color.empty()) {
    if (l.color.size() != 3) throw SceneError(m.file, what + ": color must have 3 numbers");
    out.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
  }
  if (!(l.intensity >= 0.0)) throw SceneError(m.file, what + ": intensity must not be negative");
  if (!(l.range >= 0.0)) throw SceneError(m.file, what + ": range must be positive");
  out.intensity = float(l.intensity);
  out.range = float(l.range);
  const glm::vec3 radiant = out.color * out.intensity;  // beyond float's range: an infinity
  if (!std::isfinite(radiant.x) || !std::isfinite(radiant.y) || !std::isfinite(radiant.z) ||
      !std::isfinite(out.intensity) || !std::isfinite(out.range))
    throw SceneError(m.file, what + ": color, intensity or range is beyond the range of float");
  if (out.type == LightType::Spot) {
    const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner <= outer && outer <= std::numbers::pi / 2))
      throw SceneError(m.file, what + ": spot cone angles must satisfy 0 <= inner <= outer <= pi/2");
    out.inner_cone = float(inner);
    out.outer_cone = float(outer);
  }
  out.position = glm::vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  const glm::dvec3 dir = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
  const double len = glm::length(dir);
  if (!(len > 0.0) || !std::isfinite(len))
    throw SceneError(m.file, node_what + ": the node transform gives the light no direction");
  out.direction = glm::vec3(dir / len);
  scene.lights.push_back(out);
}

// The morph weights (node.weights, else mesh.weights; none when all are 0) and skin of
// node `index`, which has a mesh. `worlds` is filled on first use.
gltf::MeshPose mesh_pose(const ModelRef& m, int index, std::vector<glm::dmat4>& worlds) {
  const tinygltf::Node& node = m.model.nodes[std::size_t(index)];
  gltf::MeshPose pose;
  const std::vector<double>& weights =
      !node.weights.empty() || std::size_t(node.mesh) >= m.model.meshes.size() ? node.weights
                                                                              : m.model.meshes[std::size_t(node.mesh)].weights;
  for (double w : weights) {
    if (!std::isfinite(w))
      throw SceneError(m.file, "node " + std::to_string(index) + ": non-finite morph target weight");
    if (w != 0.0) pose.morph_weights = weights;
  }
  if (node.skin >= 0) {
    if (worlds.empty()) worlds = gltf::node_worlds(m);
    pose.joints = gltf::joint_matrices(m, node.skin, worlds);
  }
  return pose;
}

// Where the scene's nodes are at each of the shutter's kShutterSteps times: one scene_nodes
// list per time, in the same order (the hierarchy does not move). Leaves the model posed
// at the shutter's opening.
std::vector<std::vector<gltf::NodeInstance>> nodes_over_shutter(tinygltf::Model& model, const std::string& file,
                                                               int scene_index, const Shutter& shutter) {
  std::vector<std::vector<gltf::NodeInstance>> steps;
  for (int k = kShutterSteps - 1; k >= 0; --k) {
    const double t = shutter.open + (shutter.close - shutter.open) * double(k) / double(kShutterSteps - 1);
    gltf::pose_animation(model, file, t, /*warn=*/false);
    steps.push_back(gltf::scene_nodes(ModelRef{model, file, scene_index}));
  }
  std::reverse(steps.begin(), steps.end());
  return steps;
}

// The world matrices of drawing `index` (in scene_nodes order) over the shutter, times
// `local` (an EXT_mesh_gpu_instancing transform); empty when it does not move.
std::vector<glm::dmat4> drawing_motion(const std::vector<std::vector<gltf::NodeInstance>>& steps, std::size_t index,
                                       const glm::dmat4& local) {
  if (steps.empty()) return {};
  bool moves = false;
  for (const auto& step : steps) moves |= step[index].world != steps[0][index].world;
  if (!moves) return {};
  std::vector<glm::dmat4> worlds;
  for (const auto& step : steps) worlds.push_back(step[index].world * local);
  return worlds;
}

Scene scene_from_model(const tinygltf::Model& model, const std::string& file, int scene_index,
                       InstancingMode instancing,
                       const std::vector<std::vector<gltf::NodeInstance>>& steps = {}) {
  const ModelRef m{model, file, scene_index};
  // A required extension Lancer lacks was refused already (check_gltf_json); one the file
  // only uses is rendered without, and the user is told which.
  for (const std::string& used : model.extensionsUsed)
    if (!gltf::extension_supported(used))
      print_scene_warnings(file, "extension " + used + " is not supported: the scene is rendered without it");

  Scene scene;
  scene.source = file;
  gltf::read_textures_and_images(m, scene);
  gltf::read_materials(m, scene);

  SceneBuilder builder(scene, file);
  gltf::PrimitiveEmitter emitter(m, scene, builder);
  gltf::MeshSharing sharing(m, scene, emitter, instancing);
  std::vector<glm::dmat4> worlds;  // of every node, for skins' joints (computed once, if needed)
  const std::vector<gltf::NodeInstance> nodes = gltf::scene_nodes(m);
  // First which meshes are drawn often enough to share one copy (or move), then the drawings.
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const gltf::NodeInstance& inst = nodes[j];
    const tinygltf::Node& node = model.nodes[std::size_t(inst.node)];
    if (node.mesh < 0) continue;
    const gltf::MeshPose pose = mesh_pose(m, inst.node, worlds);
    const bool posed = !pose.morph_weights.empty() || !pose.joints.empty();
    // Counting needs only how many instances there are: no bound on copies yet.
    const std::optional<std::vector<glm::dmat4>> instances = gltf::instance_transforms(m, inst.node, 0);
    const bool moves = !drawing_motion(steps, j, glm::dmat4(1.0)).empty();
    if (!instances) sharing.count(node.mesh, inst.world, posed, moves);
    if (instances)
      for (const glm::dmat4& instance : *instances) sharing.count(node.mesh, inst.world * instance, posed, moves);
  }
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const gltf::NodeInstance& inst = nodes[j];
    const tinygltf::Node& node = model.nodes[std::size_t(inst.node)];
    if (node.mesh >= 0) {
      const gltf::MeshPose pose = mesh_pose(m, inst.node, worlds);
      // Copies of a mesh that is not shared are bounded before any is made.
      const std::optional<std::vector<glm::dmat4>> instances = gltf::instance_transforms(
          m, inst.node, sharing.shared(node.mesh) ? 0 : emitter.triangle_bound(node.mesh));
      if (!instances) sharing.draw(node.mesh, inst.world, pose, drawing_motion(steps, j, glm::dmat4(1.0)));
      if (instances)
        for (const glm::dmat4& instance : *instances)
          sharing.draw(node.mesh, inst.world * instance, pose, drawing_motion(steps, j, instance));
    }
    if (node.camera >= 0) {
      add_camera(m, inst.node, node.camera, inst.world, scene);
      // A moving camera: its keys, unless a step's matrix cannot be one (then it stays).
      for (const glm::dmat4& w : drawing_motion(steps, j, glm::dmat4(1.0))) {
        const std::optional<MotionKey> key = motion_key(w);
        std::vector<MotionKey>& keys = scene.cameras.back().motion;
        if (!key || (!keys.empty() && (glm::determinant(key->stretch) < 0.0f) !=
                                          (glm::determinant(keys[0].stretch) < 0.0f))) {
          print_scene_warnings(file, "camera node " + std::to_string(inst.node) + " moves through a singular or "
                                     "mirroring transform while the shutter is open: it stays where it opens");
          keys.clear();
          break;
        }
        keys.push_back(*key);
      }
    }
    add_light(m, inst.node, inst.world, scene);
  }
  sharing.finish();
  builder.finish();
  return scene;
}

}  // namespace

namespace {

// Posed at `frame_time` (or, with a shutter, at its opening with the motion over it).
Scene scene_from_posed_model(tinygltf::Model& model, const std::string& file, int scene,
                             std::optional<double> frame_time, InstancingMode instancing,
                             std::optional<Shutter> shutter) {
  const AnimationRange animation = gltf::pose_animation(model, file, shutter ? shutter->open : frame_time);
  std::vector<std::vector<gltf::NodeInstance>> steps;
  if (shutter && shutter->close > shutter->open) steps = nodes_over_shutter(model, file, scene, *shutter);
  Scene result = scene_from_model(model, file, scene, instancing, steps);
  result.animation = animation;
  return result;
}

}  // namespace

Scene read_gltf(const std::filesystem::path& path, int scene, std::optional<double> frame_time,
                InstancingMode instancing, std::optional<Shutter> shutter) {
  const std::string file = path.string();
  // The file's bytes are freed once parsed: tinygltf keeps its own copy of the buffers.
  tinygltf::Model model = load_model(read_whole_file(path, file), path, file);
  return scene_from_posed_model(model, file, scene, frame_time, instancing, shutter);
}

Scene read_gltf_bytes(std::span<const unsigned char> bytes, const std::filesystem::path& path, int scene,
                      std::optional<double> frame_time, InstancingMode instancing, std::optional<Shutter> shutter) {
  const std::string file = path.string();
  tinygltf::Model model = load_model(bytes, path, file);
  return scene_from_posed_model(model, file, scene, frame_time, instancing, shutter);
}

}  // namespace lancer
