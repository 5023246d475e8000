// lancer-motion-bench: Lancer's motion blur beside Embree's on the same moving scene (issue
// 19). Rays: one camera ray per pixel at a stratified shutter time (stratified_time), and
// a cosine-weighted diffuse bounce from each camera hit (Lancer's two-level accelerator,
// the hit point on the surface moved to the ray's time) at the camera ray's time. The same
// rays at time 0 on the still scene (every instance where it is at shutter open) give what
// motion costs. Per set: Lancer single rays and, for camera rays, packets; Embree
// rtcIntersect1 and rtcIntersect16; each round alternates them, medians are quoted (the
// machine is shared). Agreement of Lancer's single-ray hits with rtcIntersect1's is counted
// and reported, never fatal; so is either against an exact reference on a sample.
//
//   lancer-motion-bench [--scene FILE.gltf] [--shutter OPEN,CLOSE] [--bunnies N]
//                       [--models DIR] [--rounds R] [--threads T] [--size S]
// Defaults: scenes/cornell-box-motion.gltf, shutter 0,1, 5 rounds, 512x512, every core.
// --bunnies N replaces the glTF scene by N moving Stanford bunnies (motion_scenes.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "accel/accel_factory.h"
#include "accel/ray_offset.h"
#include "motion_embree.h"
#include "motion_scenes.h"
#include "render/camera.h"
#include "render/ray_batch.h"
#include "render/ray_sets.h"
#include "render/sampler.h"
#include "render/surface.h"
#include "scene/load_scene.h"

namespace lancer::bench {
namespace {

struct Options {
  std::filesystem::path scene = LANCER_BENCH_SCENES_DIR "/cornell-box-motion.gltf";
  Shutter shutter{0.0, 1.0};
  int bunnies = 0;
  std::filesystem::path models = LANCER_BENCH_MODELS_DIR;
  int rounds = 5;
  int threads = 0;
  int size = 512;
};

// One version of the scene (blurred or still) with both tracers built on it.
struct Version {
  const char* name;
  Scene scene;
  std::unique_ptr<Accelerator> lancer;
  std::unique_ptr<EmbreeMotionScene> embree;
};

// The four ways of tracing a set that are timed, in the order each round runs them.
enum Way { kLancerSingle, kEmbree1, kLancerPacket, kEmbree16, kWays };

struct Agreement {
  std::size_t rays = 0, agree = 0, other_hit = 0, other_t = 0;
  double share() const { return rays ? 100.0 * double(agree) / double(rays) : 0.0; }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Same (instance, source triangle) or both miss, and t within 1e-4 relative.
Agreement agreement(const Scene& scene, const std::vector<Hit>& a, const std::vector<Hit>& b) {
  Agreement g;
  g.rays = a.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!a[i].valid() || !b[i].valid()) {
      (a[i].valid() == b[i].valid() ? g.agree : g.other_hit)++;
    } else if (a[i].instance != b[i].instance ||
               scene.source_id(a[i].prim, a[i].instance) != scene.source_id(b[i].prim, b[i].instance)) {
      ++g.other_hit;
    } else {
      (std::abs(a[i].t - b[i].t) <= 1e-4f * std::max(a[i].t, b[i].t) ? g.agree : g.other_t)++;
    }
  }
  return g;
}

std::vector<Hit> trace(const Version& v, Way way, const std::vector<Ray>& rays, tbb::task_arena& arena) {
  std::vector<Hit> hits(rays.size());
  if (way == kLancerSingle || way == kLancerPacket) {
    trace_closest(*v.lancer, rays, way == kLancerSingle ? TraceMode::Single : TraceMode::Packet, arena, hits);
  } else {
    for_each_ray_chunk(arena, rays.size(), [&](std::size_t first, std::size_t count) {
      v.embree->intersect(way == kEmbree1, rays.data() + first, hits.data() + first, count);
    });
  }
  return hits;
}

// Camera rays at stratified shutter times, and a diffuse bounce from each of their hits.
void make_rays(const Version& blurred, const PinholeCamera& camera, tbb::task_arena& arena, std::vector<Ray>& cam,
               std::vector<Ray>& diffuse) {
  cam = primary_rays(camera);
  for (std::size_t i = 0; i < cam.size(); ++i) {
    const auto [x, y] = tile_order_pixel(i, camera.width());
    cam[i].time = stratified_time(x, y);
  }
  const std::vector<Hit> hits = trace(blurred, kLancerSingle, cam, arena);
  diffuse.clear();
  for (std::size_t i = 0; i < cam.size(); ++i) {
    if (!hits[i].valid()) continue;
    const SurfacePoint sp = make_surface_point(blurred.scene, cam[i], hits[i]);  // moved to cam[i].time
    const auto [x, y] = tile_order_pixel(i, camera.width());
    PixelSampler sampler(std::uint32_t(x), std::uint32_t(y), 0, 1);
    const float u1 = sampler.next();
    const float u2 = sampler.next();
    Ray r;
    r.org = offset_ray_origin(sp.p, sp.ng);
    r.dir = cosine_hemisphere_direction(sp.ng, u1, u2);
    r.time = cam[i].time;
    diffuse.push_back(r);
  }
}

// Over the bunnies from above at an angle, as lancer-instancing-bench looks at its grid.
PinholeCamera bunnies_camera(const Bounds3& box, int size) {
  const glm::vec3 centre = box.center(), extent = box.extent();
  const glm::vec3 eye = centre + glm::vec3(-0.3f * extent.x, 0.25f * std::max(extent.x, extent.z) + extent.y,
                                           -0.3f * extent.z);
  return PinholeCamera::look_at(eye, centre, {0, 1, 0}, 0.9f, size, size);
}

std::vector<Ray> at_time_zero(std::vector<Ray> rays) {
  for (Ray& r : rays) r.time = 0.0f;
  return rays;
}

std::string cell(double x, bool present) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", x);
  return present ? b : "–";
}

// One line per tracer on a sample of the blurred rays (every 67th), against the
// exact reference: what can be checked before the two-level accelerator moves instances.
void check_against_reference(const Version& blurred, const char* set, const std::vector<Ray>& rays,
                             tbb::task_arena& arena) {
  std::vector<Ray> sample;
  for (std::size_t i = (rays.size() % 64) / 2; i < rays.size(); i += 67) sample.push_back(rays[i]);
  const MotionReference reference(blurred.scene);
  std::vector<Hit> expected(sample.size());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sample.size()), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) expected[i] = reference.intersect(sample[i]);
    });
  });
  for (Way way : {kLancerSingle, kEmbree1}) {
    if (way == kEmbree1 && !blurred.embree) continue;
    const Agreement g = agreement(blurred.scene, trace(blurred, way, sample, arena), expected);
    std::printf("- %s rays, %zu sampled, %s vs exact reference: %.2f%% agree (%zu other hit, %zu other t)\n", set,
                g.rays, way == kEmbree1 ? "Embree rtcIntersect1" : "Lancer single", g.share(), g.other_hit,
                g.other_t);
  }
}

int run(const Options& opt) {
  tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
  arena.initialize();
  Version blurred{"blurred", {}, nullptr, nullptr};
  if (opt.bunnies > 0) {
    blurred.scene = moving_bunnies(load_scene(opt.models / "stanford-bunny.obj"), opt.bunnies);
  } else {
    blurred.scene = load_scene(opt.scene, std::nullopt, std::nullopt, InstancingMode::Auto, opt.shutter);
  }
  Version still{"still", still_copy(blurred.scene), nullptr, nullptr};
  const bool with_embree = motion_embree_available();
  for (Version* v : {&blurred, &still}) {
    arena.execute([&] { v->lancer = make_accelerator("kdtree", v->scene.triangles, v->scene.instancing); });
    if (with_embree) v->embree = std::make_unique<EmbreeMotionScene>(v->scene, arena.max_concurrency());
  }
  const Scene& s = blurred.scene;
  const PinholeCamera camera = opt.bunnies > 0     ? bunnies_camera(s.bounds(), opt.size)
                               : s.cameras.empty() ? PinholeCamera::framing(s.bounds(), opt.size, opt.size)
                                                   : PinholeCamera::from_desc(s.cameras.front(), opt.size, opt.size);
  std::vector<Ray> sets[2][2];  // [set: camera, diffuse][version: blurred, still]
  make_rays(blurred, camera, arena, sets[0][0], sets[1][0]);
  for (auto& set : sets) set[1] = at_time_zero(set[0]);

  std::printf("# %s: %zu triangles stored, %zu drawn, %zu instances (%zu moving, %zu keys each); shutter %g,%g\n",
              opt.bunnies > 0 ? s.source.c_str() : opt.scene.filename().string().c_str(), s.triangle_count(),
              s.drawn_triangle_count(), s.instancing.instances.size(), s.instancing.motions.size(),
              s.instancing.motions.empty() ? std::size_t(0) : s.instancing.motions.front().keys.size(),
              opt.shutter.open, opt.shutter.close);
  std::printf("# %s", motion_embree_description().c_str());
  if (with_embree)
    std::printf("; moving instances as quaternion decompositions: %zu, as matrices (linear interpolation): %zu",
                blurred.embree->quaternion_instances(), blurred.embree->matrix_instances());
  std::printf("\n# %dx%d camera rays, %zu diffuse; %d thread(s), %d rounds, medians\n\n", opt.size, opt.size,
              sets[1][0].size(), arena.max_concurrency(), opt.rounds);

  std::vector<double> mrays[2][2][kWays];
  const auto timed = [&](int set, int ver, Way way) {
    const Version& v = ver == 0 ? blurred : still;
    const auto t0 = std::chrono::steady_clock::now();
    trace(v, way, sets[set][ver], arena);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    mrays[set][ver][way].push_back(double(sets[set][ver].size()) / secs * 1e-6);
  };
  for (int round = 0; round < opt.rounds; ++round)
    for (int set = 0; set < 2; ++set)
      for (int ver = 0; ver < 2; ++ver)
        for (int way = 0; way < kWays; ++way) {
          if ((way == kEmbree1 || way == kEmbree16) && !with_embree) continue;
          if (way == kLancerPacket && set != 0) continue;
          timed(set, ver, Way(way));
        }

  const char* set_names[2] = {"camera", "diffuse"};
  std::printf("| set | scene | Lancer 1 Mrays/s | Lancer packets | Embree 1 | Embree 16 | Lancer/Embree 1 "
              "| packets/Embree 16 | agree %% | other hit | other t |\n");
  std::printf("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  for (int set = 0; set < 2; ++set)
    for (int ver = 0; ver < 2; ++ver) {
      const Version& v = ver == 0 ? blurred : still;
      double m[kWays];
      for (int w = 0; w < kWays; ++w) m[w] = median(mrays[set][ver][w]);
      Agreement g;
      if (with_embree)
        g = agreement(v.scene, trace(v, kLancerSingle, sets[set][ver], arena),
                      trace(v, kEmbree1, sets[set][ver], arena));
      std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", set_names[set], v.name,
                  cell(m[kLancerSingle], true).c_str(), cell(m[kLancerPacket], set == 0).c_str(),
                  cell(m[kEmbree1], with_embree).c_str(), cell(m[kEmbree16], with_embree).c_str(),
                  cell(m[kLancerSingle] / m[kEmbree1], with_embree).c_str(),
                  cell(m[kLancerPacket] / m[kEmbree16], with_embree && set == 0).c_str(),
                  cell(g.share(), with_embree).c_str(), with_embree ? std::to_string(g.other_hit).c_str() : "–",
                  with_embree ? std::to_string(g.other_t).c_str() : "–");
    }

  std::printf("\nCost of motion, time blurred / still (Mrays/s still / blurred):\n\n");
  std::printf("| set | Lancer 1 | Lancer packets | Embree 1 | Embree 16 |\n|---|--:|--:|--:|--:|\n");
  for (int set = 0; set < 2; ++set) {
    double c[kWays];
    for (int w = 0; w < kWays; ++w) c[w] = median(mrays[set][1][w]) / median(mrays[set][0][w]);
    std::printf("| %s | %s | %s | %s | %s |\n", set_names[set], cell(c[kLancerSingle], true).c_str(),
                cell(c[kLancerPacket], set == 0).c_str(), cell(c[kEmbree1], with_embree).c_str(),
                cell(c[kEmbree16], with_embree).c_str());
  }
  std::printf("\nChecks on the blurred rays:\n\n");
  for (int set = 0; set < 2; ++set) check_against_reference(blurred, set_names[set], sets[set][0], arena);
  return 0;
}

}  // namespace
}  // namespace lancer::bench

int main(int argc, char** argv) {
  lancer::bench::Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    try {
      if (i + 1 >= argc) throw std::invalid_argument("needs a value");
      const std::string value = argv[++i];
      if (a == "--scene") opt.scene = value;
      else if (a == "--shutter") {
        const std::size_t comma = value.find(',');
        if (comma == std::string::npos) throw std::invalid_argument("want OPEN,CLOSE");
        opt.shutter = {std::stod(value.substr(0, comma)), std::stod(value.substr(comma + 1))};
      } else if (a == "--bunnies") opt.bunnies = std::stoi(value);
      else if (a == "--models") opt.models = value;
      else if (a == "--rounds") opt.rounds = std::max(1, std::stoi(value));
      else if (a == "--threads") opt.threads = std::stoi(value);
      else if (a == "--size") opt.size = std::stoi(value);
      else throw std::invalid_argument("unknown option");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lancer-motion-bench: bad argument '%s': %s\n", a.c_str(), e.what());
      return 2;
    }
  }
  try {
    return lancer::bench::run(opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lancer-motion-bench: %s\n", e.what());
    return 1;
  }
}
