#include "bench_suite.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <set>
#include <string_view>
#include <system_error>

#include <glm/geometric.hpp>

#include "scene/load_scene.h"
#include "scene/spd.h"

namespace lancer::bench {

namespace {

namespace fs = std::filesystem;

// SPD sizes of the default suite: 262,402 (balls), 36,866 (gears), 34,048 (mount),
// 633,602 (rings) and 65,536 (tetra) triangles with the default tessellation.
struct SpdChoice {
  const char* name;
  int size;
};
constexpr SpdChoice kDefaultSpd[] = {{"balls", 3}, {"gears", 4}, {"mount", 7}, {"rings", 5}, {"tetra", 8}};

const char* const kBuiltIn[] = {"cornell-box", "cornell-box-spheres"};

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".obj" || ext == ".gltf" || ext == ".glb";
}

// "<generator>-<size>" with a known generator and a size in its range, else nothing.
std::optional<SuiteScene> parse_spd_name(const std::string& name) {
  const std::size_t dash = name.rfind('-');
  if (dash == std::string::npos || dash + 1 >= name.size()) return std::nullopt;
  const std::string generator = name.substr(0, dash), digits = name.substr(dash + 1);
  if (!std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }) || digits.size() > 4)
    return std::nullopt;
  const auto& names = spd_names();
  if (std::find(names.begin(), names.end(), std::string_view(generator)) == names.end()) return std::nullopt;
  const int size = std::stoi(digits);
  const SpdSizeRange range = spd_size_range(generator);
  if (size < range.min || size > range.max) return std::nullopt;
  return spd_entry(generator, size);
}

// A camera for scenes without one: a three-quarter view from the front (+z), above and to
// the right, at the distance where the scene's bounding box just fits the 45 degree field of
// view (every corner projected), so the scene fills the image. (PinholeCamera::framing fits
// the bounding sphere instead, which leaves long thin meshes a few percent of the pixels.)
PinholeCamera framing_camera(const Bounds3& box, int size) {
  constexpr float kFov = 0.7853981634f;
  const glm::vec3 c = box.center();
  const glm::vec3 w = glm::normalize(glm::vec3(0.3f, 0.45f, 1.0f));  // from the centre toward the eye
  const glm::vec3 u = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), w));
  const glm::vec3 v = glm::cross(w, u);
  const float tan_half = std::tan(0.5f * kFov);
  float distance = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                      (corner & 4) ? box.hi.z : box.lo.z);
    const glm::vec3 rel = p - c;
    const float spread = std::max(std::fabs(glm::dot(rel, u)), std::fabs(glm::dot(rel, v)));
    distance = std::max(distance, glm::dot(rel, w) + spread / tan_half);
  }
  if (!(distance > 0.0f)) distance = 1.0f;
  return PinholeCamera::look_at(c + w * (1.02f * distance), c, glm::vec3(0.0f, 1.0f, 0.0f), kFov, size, size);
}

bool has_light(const Scene& scene) {
  if (!scene.lights.empty()) return true;
  return std::any_of(scene.material_id.begin(), scene.material_id.end(),
                     [&](std::uint32_t id) { return scene.materials[id].emissive(); });
}

}  // namespace

SuiteScene spd_entry(const std::string& generator, int size) {
  SuiteScene s;
  s.name = generator + "-" + std::to_string(size);
  s.origin = "spd";
  s.kind = SuiteScene::Kind::Spd;
  s.spd = generator;
  s.spd_size = size;
  return s;
}

std::vector<SuiteScene> default_suite(const fs::path& scenes_dir, const fs::path& models_dir) {
  std::vector<SuiteScene> suite;
  std::set<std::string> taken;
  for (const char* name : kBuiltIn) {
    SuiteScene s;
    s.name = name;
    s.origin = "built-in";
    s.file = scenes_dir / (std::string(name) + ".gltf");
    suite.push_back(s);
    taken.insert(s.name);
  }
  for (const SpdChoice& c : kDefaultSpd) {
    suite.push_back(spd_entry(c.name, c.size));
    taken.insert(suite.back().name);
  }
  // The shared meshes are optional: a folder that is not there adds nothing (lancer-bench
  // refuses a --models folder that does not exist before this).
  std::error_code absent;
  if (models_dir.empty() || !fs::is_directory(models_dir, absent)) return suite;
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(models_dir))
    if (e.is_regular_file() && is_mesh_file(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    SuiteScene s;
    s.name = f.stem().string();
    if (!taken.insert(s.name).second) s.name = f.filename().string();
    taken.insert(s.name);
    s.origin = "models";
    s.file = f;
    suite.push_back(s);
  }
  return suite;
}

std::vector<SuiteScene> select_scenes(const std::vector<SuiteScene>& suite, const std::vector<std::string>& names) {
  std::vector<SuiteScene> out;
  for (const std::string& name : names) {
    if (std::any_of(out.begin(), out.end(), [&](const SuiteScene& s) { return s.name == name; })) continue;
    const auto found = std::find_if(suite.begin(), suite.end(), [&](const SuiteScene& s) { return s.name == name; });
    if (found != suite.end()) {
      out.push_back(*found);
      continue;
    }
    if (auto spd = parse_spd_name(name)) {
      out.push_back(*spd);
      continue;
    }
    std::string known;
    for (const SuiteScene& s : suite) known += (known.empty() ? "" : ", ") + s.name;
    throw UnknownScene("--scenes: unknown scene '" + name + "' (known: " + known +
                       "; or <spd>-<size> with spd balls, gears, mount, rings or tetra)");
  }
  return out;
}

BenchScene load_bench_scene(const SuiteScene& entry, int size) {
  Scene scene = entry.kind == SuiteScene::Kind::Spd ? make_spd(entry.spd, entry.spd_size) : load_scene(entry.file);
  const PinholeCamera camera = scene.cameras.empty() ? framing_camera(scene.bounds(), size)
                                                     : PinholeCamera::from_desc(scene.cameras.front(), size, size);
  bool added = false;
  if (!has_light(scene)) {
    const Bounds3 b = scene.bounds();
    const glm::vec3 e = b.extent();
    const float diag = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    PunctualLight light;
    light.name = "lancer-bench light";
    light.type = LightType::Point;
    // Above and to the left of the camera, so that the mesh shadows part of itself.
    light.position = b.center() + glm::vec3(-0.5f, 1.0f, 0.3f) * diag;
    scene.lights.push_back(light);
    added = true;
  }
  return BenchScene{std::move(scene), camera, added};
}

}  // namespace lancer::bench
