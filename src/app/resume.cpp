#include "app/resume.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "render/content_hash.h"

#ifndef LANCER_VERSION
#define LANCER_VERSION "unknown"
#endif

namespace lancer {

namespace {

namespace fs = std::filesystem;

// Floats as hex (%a): exact, so a camera a rounding away still counts as another.
std::string exact(float v) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", static_cast<double>(v));
  return text;
}
std::string exact(const glm::vec3& v) { return exact(v.x) + "," + exact(v.y) + "," + exact(v.z); }
std::string exact(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", v);
  return text;
}

// Adds the file's bytes; a file that cannot be read adds its name and a marker instead (the
// scene loaded, so it was there a moment ago).
void add_file(ContentHash& h, const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  h.add(in.bad() || !in.is_open() ? "unreadable " + file.string() : bytes);
}

template <typename T>
void add_vector(ContentHash& h, const T& v) {
  h.add_u64(v.size());
  h.add(v.data(), v.size() * sizeof(v[0]));
}

// The --flag a fact comes from, for the messages.
std::string label(const std::string& key) {
  if (key == "maxDepth") return "--max-depth";
  if (key == "lightSamples") return "--light-samples";
  if (key == "causticK") return "--caustic-k";
  if (key == "causticRadius") return "--caustic-radius";
  if (key == "frameTime") return "--frame-time";
  if (key == "shutter") return "--shutter";
  if (key == "emitterSamples") return "camera rays per sample on visible lights (render/camera_emission.h)";
  if (key == "lightTracedCaustics") return "light-traced caustics (render/light_tracer.h)";
  return "--" + key;
}

}  // namespace

std::string scene_fingerprint(const std::string& file, const Scene& scene) {
  ContentHash h;
  add_file(h, file);
  std::string ext = fs::path(file).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") {  // its materials live in the mtllib files
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
      std::istringstream words(line);
      std::string word;
      if (!(words >> word) || word != "mtllib") continue;
      while (words >> word) add_file(h, fs::path(file).parent_path() / word);
    }
  }
  const TriangleSoA& t = scene.triangles;
  for (int k = 0; k < 3; ++k) add_vector(h, t.x[k]), add_vector(h, t.y[k]), add_vector(h, t.z[k]);
  add_vector(h, scene.material_id);
  add_vector(h, scene.attrib_flags);
  add_vector(h, scene.normals);
  add_vector(h, scene.texcoords);
  add_vector(h, scene.tangents);
  add_vector(h, scene.texcoords1);
  add_vector(h, scene.colors);
  // Instances: a render resumed with other --instancing has other geometry (in rounding).
  h.add_u64(scene.instancing.meshes.size());
  for (const MeshRange& m : scene.instancing.meshes) h.add_u64(std::uint64_t(m.first) << 32 | m.count);
  h.add_u64(scene.instancing.motions.size());
  for (const InstanceMotion& motion : scene.instancing.motions) add_vector(h, motion.keys);
  h.add_u64(scene.instancing.instances.size());
  for (const Instance& inst : scene.instancing.instances) {
    h.add_u64(inst.mesh);
    h.add_u64(inst.motion);
    for (const Affine* a : {&inst.to_world, &inst.to_object}) {
      h.add(&a->linear, sizeof a->linear);
      h.add(&a->offset, sizeof a->offset);
    }
  }
  for (const PunctualLight& light : scene.lights) {
    const float numbers[] = {light.color.x, light.color.y, light.color.z, light.intensity, light.position.x,
                             light.position.y, light.position.z, light.direction.x, light.direction.y,
                             light.direction.z, light.range, light.inner_cone, light.outer_cone};
    h.add_u64(static_cast<std::uint64_t>(light.type));
    h.add(numbers, sizeof numbers);
  }
  for (const Image& image : scene.images) {
    h.add_u64(static_cast<std::uint64_t>(image.width) << 32 | static_cast<std::uint32_t>(image.height));
    h.add_u64(static_cast<std::uint64_t>(image.channels));
    add_vector(h, image.pixels);
  }
  return h.hex();
}

CheckpointFacts render_facts(const RenderOptions& options, const RenderSettings& settings, const Scene& scene,
                             const PinholeCamera& camera) {
  std::string environment = "none";
  if (!options.env_file.empty()) {
    ContentHash h;
    add_file(h, options.env_file);
    environment = "map " + h.hex() + " scale " + exact(options.env_scale);
  } else if (!options.env_color.empty()) {
    environment = "color " + exact(options.env_scale * glm::vec3(options.env_color[0], options.env_color[1],
                                                                  options.env_color[2]));
  }
  const std::string camera_text = std::string(camera.orthographic() ? "orthographic" : "perspective") + " origin " +
                                  exact(camera.origin()) + " forward " + exact(camera.forward()) + " x " +
                                  exact(camera.x_axis()) + " y " + exact(camera.y_axis()) + " aperture " +
                                  exact(camera.aperture_radius()) + " focus " + exact(camera.focus_distance());
  // Before the scene: another --instancing that shares other meshes stores other geometry,
  // and this names the cause (one that shares the same is the same render).
  const std::string instancing = scene.instancing.empty()
                                     ? std::string("none")
                                     : std::to_string(scene.instancing.instances.size()) + " instances";
  return {{"version", LANCER_VERSION},
          {"instancing", instancing},
          {"scene", scene_fingerprint(options.scene, scene)},
          {"seed", std::to_string(settings.seed)},
          {"width", std::to_string(settings.width)},
          {"height", std::to_string(settings.height)},
          {"integrator", std::string(integrator_name(settings.integrator))},
          {"maxDepth", std::to_string(settings.max_depth)},
          {"lightSamples", std::to_string(settings.light_samples)},
          // Not an option, but a render from before it (or with another count) would mix two
          // estimators of the emission seen directly: the same expectation, other bytes.
          {"emitterSamples", std::to_string(settings.emitter_samples)},
          // Nor an option: a render from before the light-traced caustics (render/light_tracer.h)
          // counted them in its samples at full weight.
          {"lightTracedCaustics", settings.light_traced_caustics ? "1" : "0"},
          {"filter", settings.filter == PixelFilterType::Gaussian ? "gaussian" : "box"},
          {"camera", camera_text},
          {"environment", environment},
          {"frameTime", options.frame_time ? exact(*options.frame_time) : "none"},
          {"shutter", options.shutter ? exact(options.shutter->at(0)) + "," + exact(options.shutter->at(1)) : "none"},
          // The caustic photon map's (--integrator photon; 0: its defaults, which follow the size).
          {"photons", std::to_string(settings.photons)},
          {"causticK", std::to_string(settings.caustic_k)},
          {"causticRadius", exact(settings.caustic_radius)},
          {"spp", std::to_string(settings.spp)}};
}

void check_resumable(const Checkpoint& checkpoint, const CheckpointFacts& now, const std::string& file) {
  const std::string head = "--resume " + file + ": ";
  for (const auto& [key, value] : now) {
    if (key == "spp") continue;  // a resume may go on to more samples
    const std::string* then = nullptr;
    for (const auto& [k, v] : checkpoint.facts)
      if (k == key) then = &v;
    if (then == nullptr) throw std::invalid_argument(head + "it does not record the " + label(key) + " it was rendered with");
    if (*then == value) continue;
    if (key == "version")
      throw std::invalid_argument(head + "it was written by lancer " + *then + ", this is lancer " + value);
    if (key == "scene")
      throw std::invalid_argument(head + "it was rendered from another scene (the scene's files, or what they hold, "
                                         "differ from those of this render)");
    if (key == "environment")
      throw std::invalid_argument(head + "it was rendered with another environment (--env, --env-color, --env-scale)");
    if (key == "camera")
      throw std::invalid_argument(head + "it was rendered through another camera (--camera, --eye, --look-at, --up, "
                                         "--fov, --aperture, --focus-distance, or the scene's own)");
    throw std::invalid_argument(head + "it was rendered with " + label(key) + " " + *then + ", this render has " +
                                label(key) + " " + value);
  }
}

RenderState take_resumed_state(Checkpoint checkpoint, const RenderOptions& options, RenderSettings& settings,
                               const Scene& scene, const PinholeCamera& camera, int open_spp, CheckpointFacts& facts) {
  const std::string head = "--resume " + options.resume + ": ";
  if (!options.spp_given && options.time_limit_s <= 0.0) {
    for (const auto& [key, value] : checkpoint.facts)
      if (key == "spp") {
        int spp = 0;
        const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), spp);
        if (error != std::errc() || end != value.data() + value.size() || spp < 1)
          throw std::invalid_argument(head + "its spp fact '" + value + "' is not a sample count: the file is damaged");
        settings.spp = spp;
      }
    if (settings.spp == open_spp)
      throw std::invalid_argument(head + "it was a --time render without --spp; give --spp N or --time S to say how "
                                         "far to go on");
  }
  facts = render_facts(options, settings, scene, camera);
  check_resumable(checkpoint, facts, options.resume);
  const RenderState& state = checkpoint.state;
  if (state.count.empty()) throw std::invalid_argument(head + "it holds no pixels");
  const std::uint32_t most = *std::max_element(state.count.begin(), state.count.end());
  if (static_cast<std::int64_t>(most) > settings.spp)
    throw std::invalid_argument(head + "it already has " + std::to_string(most) + " samples per pixel, more than --spp " +
                                std::to_string(settings.spp));
  return std::move(checkpoint.state);
}

}  // namespace lancer
