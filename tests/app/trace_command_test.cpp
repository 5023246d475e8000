// `lancer rays` and `lancer trace`, in-process (run_cli) and as the real binary: the
// answers equal the oracle's bit for bit, with source triangle ids; packet and single
// modes and thread counts give the same bytes; bad files exit 1, bad options exit 2.
#include "app/cli.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "accel/brute_force.h"
#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "render/ray_file.h"
#include "scene/load_scene.h"
#include "simd/isa.h"
#include "test_paths.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

struct CliResult {
  int code;
  std::string out, err;
};

CliResult run(std::vector<std::string> args) {
  args.insert(args.begin(), "lancer");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

// This process's folder, removed when it exits.
fs::path temp_dir() {
  static const test::TempDir dir("lancer_trace_test");
  return dir.path();
}

std::string file_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string cornell() { return (test::scenes_dir() / "cornell-box.gltf").string(); }

// What the hit file must hold for `rays`: the oracle's closest hits, ids as source ids.
std::vector<HitRecord> oracle_hits(const Scene& scene, const std::vector<Ray>& rays) {
  const BruteForce brute(scene.triangles);
  std::vector<HitRecord> hits;
  for (const Ray& r : rays) {
    const Hit h = brute.intersect(r);
    hits.push_back(h.valid() ? HitRecord{h.t, scene.source_triangle_id[h.prim]} : HitRecord{});
  }
  return hits;
}

void expect_same_hits(const std::vector<HitRecord>& got, const std::vector<HitRecord>& expected, const std::string& what) {
  ASSERT_EQ(got.size(), expected.size()) << what;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(got[i].t) == std::bit_cast<std::uint32_t>(expected[i].t) &&
        got[i].id == expected[i].id)
      continue;
    if (++bad <= 5)
      ADD_FAILURE() << what << ": ray " << i << " got t " << got[i].t << " id " << got[i].id << ", oracle t "
                    << expected[i].t << " id " << expected[i].id;
  }
  EXPECT_EQ(bad, 0u) << what;
}

std::size_t count_hits(const std::vector<HitRecord>& hits) {
  std::size_t n = 0;
  for (const HitRecord& h : hits) n += h.id != kNoHit ? 1 : 0;
  return n;
}

// An OBJ whose first face is degenerate (dropped by the reader, source id 0), then a unit
// quad in z = 0 fanned into source triangles 1 (x > y) and 2 (y > x). No lights.
fs::path obj_with_a_dropped_triangle() {
  const fs::path file = temp_dir() / "dropped.obj";
  write_text(file,
             "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\n"
             "f 1 2 3\n"
             "f 1 2 5 4\n");
  return file;
}

Ray down_at(float x, float y) {
  Ray r;
  r.org = glm::vec3(x, y, 1.0f);
  r.dir = glm::vec3(0.0f, 0.0f, -1.0f);
  return r;
}

TEST(TraceCli, HelpDescribesTheOptions) {
  const CliResult top = run({"--help"});
  EXPECT_NE(top.out.find("trace"), std::string::npos);
  EXPECT_NE(top.out.find("rays"), std::string::npos);
  const CliResult trace = run({"trace", "--help"});
  EXPECT_EQ(trace.code, 0);
  for (const char* text : {"--rays", "--hits", "--mode", "--isa", "--threads", "--occlusion", "packet", "single",
                           "occlusion packets"})
    EXPECT_NE(trace.out.find(text), std::string::npos) << text;
  const CliResult rays = run({"rays", "--help"});
  EXPECT_EQ(rays.code, 0);
  for (const char* text : {"--set", "--output", "--width", "--height", "--seed", "primary", "diffuse", "shadow"})
    EXPECT_NE(rays.out.find(text), std::string::npos) << text;
}

TEST(TraceCli, RaysThenTraceGivesTheOraclesHitsInEveryModeAndThreadCount) {
  const fs::path dir = temp_dir();
  const Scene scene = load_scene(cornell());
  for (const char* set : {"primary", "diffuse", "shadow"}) {
    const fs::path rays_file = dir / (std::string(set) + ".rays");
    const CliResult made =
        run({"rays", cornell(), "--set", set, "-o", rays_file.string(), "--width", "64", "--height", "48", "--seed", "2"});
    ASSERT_EQ(made.code, 0) << made.err;
    const std::vector<Ray> rays = read_rays(rays_file);
    EXPECT_NE(made.out.find("lancer rays: " + std::to_string(rays.size()) + " " + set + " rays (64x48"),
              std::string::npos)
        << made.out;
    if (std::string(set) == "primary") {
      EXPECT_EQ(rays.size(), 64u * 48u);
    }
    const std::vector<HitRecord> expected = oracle_hits(scene, rays);

    const fs::path packet = dir / (std::string(set) + ".packet.hits");
    const fs::path single = dir / (std::string(set) + ".single.hits");
    const CliResult p = run({"trace", cornell(), "--rays", rays_file.string(), "--hits", packet.string(), "--mode",
                             "packet", "--threads", "2"});
    ASSERT_EQ(p.code, 0) << p.err;
    const CliResult s = run({"trace", cornell(), "--rays", rays_file.string(), "--hits", single.string(), "--mode",
                             "single", "--threads", "1"});
    ASSERT_EQ(s.code, 0) << s.err;

    EXPECT_EQ(fs::file_size(packet), rays.size() * 8);
    EXPECT_EQ(file_text(packet), file_text(single)) << set;
    expect_same_hits(read_hits(packet), expected, set);

    const std::string hits = std::string("(") + std::to_string(count_hits(expected)) + " hits)";
    EXPECT_NE(p.out.find("lancer trace: " + std::to_string(rays.size()) + " rays, packet, isa "), std::string::npos) << p.out;
    EXPECT_NE(p.out.find(", 2 threads: "), std::string::npos) << p.out;
    EXPECT_NE(p.out.find(" Mrays/s " + hits), std::string::npos) << p.out;
    EXPECT_NE(s.out.find("rays, single, isa "), std::string::npos) << s.out;
    EXPECT_NE(s.out.find(", 1 thread: "), std::string::npos) << s.out;
    EXPECT_NE(s.out.find(hits), std::string::npos) << s.out;
  }
}

// Beside the rate, trace prints what the single-ray kernel did per ray: the counts of
// measure_kd_work on the same tree, whatever the mode and the thread count.
TEST(TraceCli, PrintsTheSingleRayWorkPerRayInEveryMode) {
  const fs::path dir = temp_dir();
  const std::string spheres = (test::scenes_dir() / "cornell-box-spheres.gltf").string();
  const Scene scene = load_scene(spheres);
  const KdTree kd(scene.triangles);
  for (const char* set : {"diffuse", "shadow"}) {
    const fs::path rays_file = dir / (std::string("work.") + set + ".rays");
    ASSERT_EQ(run({"rays", spheres, "--set", set, "-o", rays_file.string(), "--width", "32", "--height", "32"}).code, 0);
    const std::vector<Ray> rays = read_rays(rays_file);
    const bool occlusion = std::string(set) == "shadow";
    const KdWorkPerRay w = measure_kd_work(kd, rays, occlusion);
    EXPECT_GT(w.inner_steps, 0.0) << set << ": a 1932-triangle tree has inner nodes";
    EXPECT_GT(w.triangle_tests, w.leaves) << set;
    char expected[256];
    std::snprintf(expected, sizeof expected,
                  "lancer trace: single-ray kernel work per ray: %.2f inner steps, %.2f leaves, %.2f triangle tests\n",
                  w.inner_steps, w.leaves, w.triangle_tests);
    for (const char* mode : {"packet", "single"})
      for (const char* threads : {"1", "2"}) {
        std::vector<std::string> args{"trace", spheres, "--rays", rays_file.string(), "--hits",
                                      (dir / "work.hits").string(), "--mode", mode, "--threads", threads};
        if (occlusion) args.push_back("--occlusion");
        const CliResult r = run(args);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.out.find(expected), std::string::npos) << set << " " << mode << " " << threads << ": " << r.out;
      }
  }
}

TEST(TraceCli, EveryIsaGivesTheSameBytesInBothModes) {
  const fs::path dir = temp_dir();
  const fs::path rays_file = dir / "isa.rays";
  ASSERT_EQ(run({"rays", cornell(), "--set", "diffuse", "-o", rays_file.string(), "--width", "32", "--height", "32"}).code, 0);
  const std::string reference_file = (dir / "isa.reference.hits").string();
  ASSERT_EQ(run({"trace", cornell(), "--rays", rays_file.string(), "--hits", reference_file, "--isa", "scalar",
                 "--mode", "single"})
                .code,
            0);
  const std::string reference = file_text(reference_file);
  for (Isa isa : supported_isas()) {
    for (const char* mode : {"packet", "single"}) {
      const std::string out = (dir / "isa.hits").string();
      const CliResult r = run({"trace", cornell(), "--rays", rays_file.string(), "--hits", out, "--isa",
                               std::string(isa_name(isa)), "--mode", mode});
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_NE(r.out.find("isa " + std::string(isa_name(isa))), std::string::npos) << r.out;
      EXPECT_EQ(file_text(out), reference) << isa_name(isa) << " " << mode;
    }
  }
}

// Rays no camera makes, mixed into the same packets as ordinary ones: infinite origins and
// directions, zero directions, empty and negative intervals, huge bounds. The tracer must
// answer them exactly as the oracle does, in both modes.
TEST(TraceCli, UnusualRaysGetTheOraclesAnswersInBothModes) {
  const fs::path dir = temp_dir();
  const Scene scene = load_scene(cornell());
  const glm::vec3 centre = 0.5f * (scene.bounds().lo + scene.bounds().hi);
  std::vector<Ray> rays;
  for (int i = 0; i < 200; ++i) {
    Ray r;
    r.org = glm::vec3(0.278f, 0.273f, -0.8f);
    r.dir = centre - r.org + glm::vec3(0.001f * static_cast<float>(i % 17) - 0.008f, 0.0f, 0.0f);
    switch (i % 10) {
      case 1: r.org.x = kInfinity; break;
      case 2: r.dir = glm::vec3(0.0f); break;
      case 3: r.dir.y = -kInfinity; break;
      case 4: r.tnear = 2.0f; r.tfar = 1.0f; break;
      case 5: r.tfar = -1.0f; break;
      case 6: r.tnear = -kInfinity; break;
      case 7: r.dir *= 1e-30f; r.tfar = 3.0e38f; break;
      case 8: r.dir = glm::vec3(0.0f, 0.0f, 1.0f); r.tfar = 1e-7f; break;
      default: break;
    }
    rays.push_back(r);
  }
  const fs::path rays_file = dir / "unusual.rays";
  write_rays(rays_file, rays);
  const std::vector<HitRecord> expected = oracle_hits(scene, read_rays(rays_file));
  ASSERT_GT(count_hits(expected), 0u);
  for (const char* mode : {"packet", "single"}) {
    const fs::path out = dir / (std::string(mode) + ".unusual.hits");
    const CliResult r = run({"trace", cornell(), "--rays", rays_file.string(), "--hits", out.string(), "--mode", mode});
    ASSERT_EQ(r.code, 0) << r.err;
    expect_same_hits(read_hits(out), expected, mode);
  }
}

TEST(TraceCli, OcclusionAnswersAreTheOraclesOneBytePerRay) {
  const fs::path dir = temp_dir();
  const fs::path rays_file = dir / "occ.rays";
  ASSERT_EQ(run({"rays", cornell(), "--set", "shadow", "-o", rays_file.string(), "--width", "64", "--height", "64"}).code, 0);
  const std::vector<Ray> rays = read_rays(rays_file);
  const Scene scene = load_scene(cornell());
  const BruteForce brute(scene.triangles);
  std::vector<std::uint8_t> expected;
  std::size_t occluded = 0;
  for (const Ray& r : rays) {
    expected.push_back(brute.occluded(r) ? 1 : 0);
    occluded += expected.back();
  }
  ASSERT_GT(occluded, 0u);
  ASSERT_LT(occluded, rays.size());

  for (const char* mode : {"packet", "single"}) {
    const fs::path out = dir / (std::string(mode) + ".occ");
    const CliResult r = run({"trace", cornell(), "--rays", rays_file.string(), "--hits", out.string(), "--occlusion",
                             "--mode", mode, "--threads", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(fs::file_size(out), rays.size());
    EXPECT_EQ(read_occlusion(out), expected) << mode;
    EXPECT_NE(r.out.find("rays, occlusion, isa "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(std::string("(") + std::to_string(occluded) + " occluded)"), std::string::npos) << r.out;
  }
}

TEST(TraceCli, HitIdsAreSourceIdsWhenTheReaderDropsTriangles) {
  const fs::path dir = temp_dir();
  const fs::path obj = obj_with_a_dropped_triangle();
  const fs::path rays_file = dir / "ids.rays";
  write_rays(rays_file, std::vector<Ray>{down_at(0.75f, 0.25f), down_at(0.25f, 0.75f), down_at(5.0f, 5.0f)});
  for (const char* mode : {"packet", "single"}) {
    const fs::path hits_file = dir / "ids.hits";
    const CliResult r = run({"trace", obj.string(), "--rays", rays_file.string(), "--hits", hits_file.string(), "--mode", mode});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("dropped 1 zero-area triangle"), std::string::npos) << r.err;
    const std::vector<HitRecord> hits = read_hits(hits_file);
    ASSERT_EQ(hits.size(), 3u);
    EXPECT_EQ(hits[0], (HitRecord{1.0f, 1u})) << mode;
    EXPECT_EQ(hits[1], (HitRecord{1.0f, 2u})) << mode;
    EXPECT_EQ(hits[2], (HitRecord{kInfinity, kNoHit})) << mode;
  }
}

TEST(TraceCli, MalformedRayFilesExit1NamingTheFileAndTheProblem) {
  const fs::path dir = temp_dir();
  const fs::path cut = dir / "cut.rays", nan = dir / "nan.rays", empty = dir / "empty.rays";
  write_text(cut, std::string(33, '\0'));
  write_text(empty, "");
  std::vector<Ray> rays(3);
  rays[1].dir.y = std::bit_cast<float>(0x7FC00000u);  // NaN in dy of ray 1
  write_rays(nan, rays);
  const struct {
    fs::path file;
    std::string problem;
  } cases[] = {{cut, "size 33 bytes is not a multiple of 32"},
               {nan, "ray 1 (byte offset 52): dy is NaN"},
               {empty, "the file is empty"},
               {dir / "missing.rays", "cannot open"}};
  for (const auto& c : cases) {
    const fs::path out = dir / "never.hits";
    const CliResult r = run({"trace", cornell(), "--rays", c.file.string(), "--hits", out.string()});
    EXPECT_EQ(r.code, 1) << c.file;
    EXPECT_NE(r.err.find(c.file.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.problem), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.file;
  }
}

TEST(TraceCli, ShadowRaysOfAScenewithoutLightsAreRefused) {
  const fs::path out = temp_dir() / "dark.rays";
  const CliResult r = run({"rays", obj_with_a_dropped_triangle().string(), "--set", "shadow", "-o", out.string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("has no light"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(TraceCli, RaySetsAreReproducibleFromTheSeed) {
  const fs::path dir = temp_dir();
  auto make = [&](const std::string& name, const std::string& seed) {
    const fs::path file = dir / name;
    EXPECT_EQ(run({"rays", cornell(), "--set", "diffuse", "-o", file.string(), "--width", "32", "--height", "16",
                   "--seed", seed})
                  .code,
              0);
    return file_text(file);
  };
  const std::string a = make("a.rays", "9"), b = make("b.rays", "9"), c = make("c.rays", "10");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(TraceCli, BadOptionsExit2) {
  const std::string rays = (temp_dir() / "opt.rays").string();
  const std::string hits = (temp_dir() / "opt.hits").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"trace", cornell(), "--hits", hits},
        {"trace", cornell(), "--rays", rays},
        {"trace", "--rays", rays, "--hits", hits},
        {"trace", cornell(), "--rays", rays, "--hits", hits, "--mode", "stream"},
        {"trace", cornell(), "--rays", rays, "--hits", hits, "--isa", "avx3"},
        {"trace", cornell(), "--rays", rays, "--hits", hits, "--threads", "-1"},
        {"trace", cornell(), "--rays", rays, "--hits", hits, "--occlusion=maybe"},
        {"trace", cornell(), "--rays", rays, "--hits", hits, "--frobnicate"},
        {"rays", cornell(), "-o", rays},
        {"rays", cornell(), "--set", "ambient", "-o", rays},
        {"rays", cornell(), "--set", "primary"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--width", "100"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--height", "12"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--width", "0"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--width", "abc"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--height", "32768"},
        {"rays", cornell(), "--set", "primary", "-o", rays, "--seed", "-1"}}) {
    const CliResult r = run(args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_EQ(r.code, 2) << joined << "\n" << r.err;
    EXPECT_FALSE(r.err.empty()) << joined;
  }
}

// The real binary: exit codes reach the shell, summaries go to stdout, errors to stderr.
TEST(TraceCliBinary, ExitCodesAndStreams) {
  const fs::path dir = temp_dir();
  const std::string bin = LANCER_BINARY;
  auto shell = [&](const std::string& args) {
    const std::string command =
        bin + " " + args + " >" + (dir / "o.txt").string() + " 2>" + (dir / "e.txt").string();
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status)) << command;
    return CliResult{WEXITSTATUS(status), file_text(dir / "o.txt"), file_text(dir / "e.txt")};
  };
  const std::string rays = (dir / "bin.rays").string();
  CliResult r = shell("rays " + cornell() + " --set primary -o " + rays + " --width 16 --height 16");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("lancer rays: 256 primary rays"), std::string::npos) << r.out;
  r = shell("trace " + cornell() + " --rays " + rays + " --hits " + (dir / "bin.hits").string() + " --threads 1");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("lancer trace: 256 rays, packet"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(dir / "bin.hits"), 256u * 8u);

  write_text(dir / "bad.rays", std::string(31, '\0'));
  r = shell("trace " + cornell() + " --rays " + (dir / "bad.rays").string() + " --hits " + (dir / "bad.hits").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("bad.rays: size 31 bytes is not a multiple of 32"), std::string::npos) << r.err;

  r = shell("trace " + cornell() + " --rays " + rays + " --hits " + (dir / "x.hits").string() + " --mode fast");
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(r.err.empty());
}

}  // namespace
}  // namespace lancer
