// lancer-instancing-bench: a grid of N Stanford bunnies drawn through instances (two-level
// kd-tree) against the same grid copied into world space (one-level), on the same rays:
// build time, memory, and camera (packets), diffuse-bounce and shadow (single rays)
// Mrays/s, alternating the two in every round and quoting medians (the machine is shared).
//
//   lancer-instancing-bench [--models DIR] [--rounds R] [--threads T] [--size S] [N ...]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <tbb/task_arena.h>

#include "accel/accel_factory.h"
#include "render/camera.h"
#include "render/ray_batch.h"
#include "render/ray_sets.h"
#include "scene/load_scene.h"

namespace lancer {
namespace {

struct Options {
  std::filesystem::path models = LANCER_BENCH_MODELS_DIR;
  int rounds = 5;
  int threads = 0;
  int size = 512;
  std::vector<int> counts = {16, 64, 256, 10000};
  std::size_t max_flat_triangles = std::size_t(20) << 20;  // copies beyond this are not built
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Bunny i of n on a square grid, turned about y and scaled, as double matrices.
glm::dmat4 placement(int i, int n, const Bounds3& box) {
  const int side = int(std::ceil(std::sqrt(double(n))));
  const double spacing = 1.3 * std::max(box.extent().x, box.extent().z);
  const double angle = 0.37 * i, scale = 0.8 + 0.4 * (i % 7) / 6.0;
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(scale * std::cos(angle), 0.0, -scale * std::sin(angle), 0.0);
  m[1] = glm::dvec4(0.0, scale, 0.0, 0.0);
  m[2] = glm::dvec4(scale * std::sin(angle), 0.0, scale * std::cos(angle), 0.0);
  m[3] = glm::dvec4(spacing * (i % side), 0.0, spacing * (i / side), 1.0);
  return m;
}

void add_light(Scene& scene) {
  PunctualLight sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  scene.lights.push_back(sun);
  scene.materials.emplace_back();
}

Scene instanced_grid(const Scene& bunny, int n) {
  Scene s;
  s.triangles = bunny.triangles;
  s.material_id.assign(bunny.triangle_count(), 0);
  s.source_triangle_id.resize(bunny.triangle_count());
  for (std::uint32_t i = 0; i < s.source_triangle_id.size(); ++i) s.source_triangle_id[i] = i;
  s.attrib_flags.assign(bunny.triangle_count(), 0);
  s.instancing.meshes.push_back({0, std::uint32_t(bunny.triangle_count())});
  const Bounds3 box = bunny.bounds();
  for (int i = 0; i < n; ++i) {
    const glm::dmat4 m = placement(i, n, box);
    const glm::dmat3 l(m), inv = glm::inverse(l);
    Instance inst;
    inst.to_world = Affine{glm::mat3(l), glm::vec3(glm::dvec3(m[3]))};
    inst.to_object = Affine{glm::mat3(inv), glm::vec3(-(inv * glm::dvec3(m[3])))};
    s.instancing.instances.push_back(inst);
    s.instance_source_base.push_back(std::uint32_t(i) * std::uint32_t(bunny.triangle_count()));
  }
  add_light(s);
  return s;
}

Scene flattened_grid(const Scene& bunny, int n) {
  Scene s;
  s.triangles.reserve(bunny.triangle_count() * std::size_t(n));
  const Bounds3 box = bunny.bounds();
  for (int i = 0; i < n; ++i) {
    const glm::dmat4 m = placement(i, n, box);
    for (std::uint32_t t = 0; t < bunny.triangle_count(); ++t) {
      glm::vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = glm::vec3(m * glm::dvec4(glm::dvec3(bunny.triangles.vertex(t, k)), 1.0));
      s.triangles.push_back(p[0], p[1], p[2]);
    }
  }
  s.material_id.assign(s.triangle_count(), 0);
  s.source_triangle_id.resize(s.triangle_count());
  for (std::uint32_t i = 0; i < s.source_triangle_id.size(); ++i) s.source_triangle_id[i] = i;
  s.attrib_flags.assign(s.triangle_count(), 0);
  add_light(s);
  return s;
}

struct Contender {
  std::string name;
  Scene scene;
  std::unique_ptr<Accelerator> accel;
  double build_s = 0.0;
  std::size_t bytes = 0;  // accelerator plus stored triangles and instances
  std::vector<double> mrays[3];
};

std::size_t scene_bytes(const Scene& s) {
  return s.triangle_count() * 9 * sizeof(float) + s.instancing.instances.size() * sizeof(Instance) +
         s.instance_source_base.size() * sizeof(std::uint32_t);
}

int run(const Options& opt) {
  const std::filesystem::path file = opt.models / "stanford-bunny.obj";
  if (!std::filesystem::exists(file)) {
    std::fprintf(stderr, "lancer-instancing-bench: %s not found (--models DIR)\n", file.string().c_str());
    return 1;
  }
  const Scene bunny = load_scene(file);
  tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
  arena.initialize();
  std::printf("# bunnies (%zu triangles each), %dx%d rays per set, %d thread(s), %d rounds, medians\n\n",
              bunny.triangle_count(), opt.size, opt.size, arena.max_concurrency(), opt.rounds);
  std::printf("| bunnies | triangles drawn | structure | build s | MiB | camera Mrays/s | diffuse Mrays/s | shadow Mrays/s |\n");
  std::printf("|--:|--:|---|--:|--:|--:|--:|--:|\n");
  for (int n : opt.counts) {
    std::vector<Contender> contenders;
    const std::size_t drawn = bunny.triangle_count() * std::size_t(n);
    contenders.push_back({"two-level", instanced_grid(bunny, n), nullptr});
    if (drawn <= opt.max_flat_triangles) contenders.push_back({"flattened", flattened_grid(bunny, n), nullptr});
    for (Contender& c : contenders) {
      const auto t0 = std::chrono::steady_clock::now();
      arena.execute([&] { c.accel = make_accelerator("kdtree", c.scene.triangles, c.scene.instancing); });
      c.build_s = seconds_since(t0);
      c.bytes = c.accel->memory_bytes() + scene_bytes(c.scene);
    }
    // The same rays for both: made on the first contender's scene.
    const Bounds3 box = contenders[0].scene.bounds();
    const glm::vec3 centre = box.center(), extent = box.extent();
    const PinholeCamera camera = PinholeCamera::look_at(
        centre + glm::vec3(-0.3f * extent.x, 0.25f * std::max(extent.x, extent.z) + extent.y, -0.3f * extent.z), centre,
        {0, 1, 0}, 0.9f, opt.size, opt.size);
    const std::vector<Ray> sets[3] = {
        primary_rays(camera), make_ray_set(contenders[0].scene, *contenders[0].accel, camera, RaySet::Diffuse, 1),
        make_ray_set(contenders[0].scene, *contenders[0].accel, camera, RaySet::Shadow, 1)};
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    for (int round = 0; round < opt.rounds; ++round)
      for (Contender& c : contenders)
        for (int set = 0; set < 3; ++set) {
          const auto t0 = std::chrono::steady_clock::now();
          if (set == 2) {
            occluded.resize(sets[set].size());
            trace_occluded(*c.accel, sets[set], TraceMode::Single, arena, occluded);
          } else {
            hits.resize(sets[set].size());
            trace_closest(*c.accel, sets[set], set == 0 ? TraceMode::Packet : TraceMode::Single, arena, hits);
          }
          c.mrays[set].push_back(double(sets[set].size()) / seconds_since(t0) * 1e-6);
        }
    for (const Contender& c : contenders)
      std::printf("| %d | %zu | %s | %.2f | %.1f | %.2f | %.2f | %.2f |\n", n, drawn, c.name.c_str(), c.build_s,
                  double(c.bytes) / (1024.0 * 1024.0), median(c.mrays[0]), median(c.mrays[1]), median(c.mrays[2]));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace lancer

int main(int argc, char** argv) {
  lancer::Options opt;
  std::vector<int> counts;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--models") opt.models = value();
      else if (a == "--rounds") opt.rounds = std::max(1, std::stoi(value()));
      else if (a == "--threads") opt.threads = std::stoi(value());
      else if (a == "--size") opt.size = std::stoi(value());
      else counts.push_back(std::stoi(a));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lancer-instancing-bench: bad argument '%s': %s\n", a.c_str(), e.what());
      return 2;
    }
  }
  if (!counts.empty()) opt.counts = counts;
  try {
    return lancer::run(opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lancer-instancing-bench: %s\n", e.what());
    return 1;
  }
}
