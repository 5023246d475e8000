// The distributed render over in-process ranks (tests/dist/in_process_render.h): the image
// and the RenderState are render_image's bit for bit for any number of ranks, threads, tile
// size and arrival order; a stop leaves a state that render_image (or another distributed
// render) resumes to the uninterrupted image; a worker that could not set up ends the
// render with its reason, and every rank ends.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "dist/local_worker.h"
#include "in_process_render.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

using test::RankSetup;

const Scene& cornell() {
  static const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  return scene;
}

const Accelerator& accel() {
  static const std::unique_ptr<Accelerator> a = make_accelerator(accelerator_names().front(), cornell().triangles);
  return *a;
}

RenderSettings settings(int width, int height, int spp, int tile_size, IntegratorKind kind = IntegratorKind::Path) {
  RenderSettings s;
  s.width = width;
  s.height = height;
  s.spp = spp;
  s.tile_size = tile_size;
  s.threads = 2;
  s.seed = 5;
  s.integrator = kind;
  if (kind == IntegratorKind::Photon) s.photons = 3000;  // a small caustic map
  return s;
}

// Ranks with these threads each (rank 0 first).
std::vector<RankSetup> ranks(std::initializer_list<int> threads) {
  std::vector<RankSetup> r;
  for (int t : threads) r.push_back(RankSetup{t, true, {}, {}});
  return r;
}

bool same_bits(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

bool same_doubles(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  // An empty vector's data() may be null, which memcmp must not be given.
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::dvec3)) == 0);
}

// The samples' sums and counts, and the light tracer's sums (render/light_tracer.h).
bool same_sums(const RenderState& a, const RenderState& b) {
  return a.width == b.width && a.height == b.height && a.count == b.count && same_doubles(a.sum, b.sum) &&
         a.light_passes == b.light_passes && a.light_paths == b.light_paths && same_doubles(a.light, b.light) &&
         same_doubles(a.pending, b.pending);
}

PinholeCamera camera_for(const RenderSettings& s) {
  return PinholeCamera::from_desc(cornell().cameras.at(0), s.width, s.height);
}

// render_image's image, filling `state` (from where it stands: empty is a fresh render).
ImageRGB one_process(const RenderSettings& s, RenderState& state, const ProgressCallback& progress = {},
                     const std::atomic<int>* stop = nullptr) {
  RenderControl control;
  control.state = &state;
  control.stop = stop;
  RenderStats stats;
  return render_image(cornell(), accel(), camera_for(s), s, stats, progress, control);
}

test::DistributedRun distributed(const RenderSettings& s, const std::vector<RankSetup>& r, RenderState& state,
                                 const ProgressCallback& progress = {}, const RenderControl& control = {},
                                 unsigned shuffle_seed = 0) {
  return test::run_distributed(cornell(), accel(), camera_for(s), s, r, state, progress, control, shuffle_seed);
}

// The uninterrupted render_image result of `s` (threads and tile size its own).
struct Reference {
  ImageRGB image;
  RenderState state;
};
Reference reference(RenderSettings s) {
  s.threads = 2;
  s.tile_size = 8;
  Reference ref;
  ref.image = one_process(s, ref.state);
  return ref;
}

// Whether a stopped render's state is one a render could continue, and its passes are the
// least any pixel has.
void expect_resumable(const RenderState& state, const RenderSettings& s) {
  EXPECT_NO_THROW(check_render_state(state, s));
  ASSERT_FALSE(state.count.empty());
  EXPECT_EQ(static_cast<std::uint32_t>(state.passes), *std::min_element(state.count.begin(), state.count.end()));
}

struct Case {
  const char* name;
  IntegratorKind integrator;
  std::vector<RankSetup> ranks;
  int width, height, spp, tile_size;
  unsigned shuffle_seed;  // 0: messages in the order sent
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class MatchesOneProcess : public ::testing::TestWithParam<Case> {};

TEST_P(MatchesOneProcess, ImageAndStateBitForBit) {
  const Case& c = GetParam();
  const RenderSettings s = settings(c.width, c.height, c.spp, c.tile_size, c.integrator);
  const Reference ref = reference(s);
  RenderState state;
  std::size_t last_done = 0, calls = 0, total = 0;
  const std::thread::id rank0 = std::this_thread::get_id();
  const test::DistributedRun run = distributed(
      s, c.ranks, state,
      [&](std::size_t done, std::size_t all) {
        EXPECT_EQ(std::this_thread::get_id(), rank0) << "progress comes on rank 0's thread";
        EXPECT_GE(done, last_done);
        last_done = done, total = all, ++calls;
      },
      {}, c.shuffle_seed);
  EXPECT_TRUE(same_bits(run.image, ref.image));
  EXPECT_TRUE(same_sums(state, ref.state));
  EXPECT_EQ(state.passes, c.spp);
  EXPECT_FALSE(run.stats.stopped);
  EXPECT_EQ(run.stats.passes, c.spp);
  EXPECT_EQ(run.stats.min_spp, static_cast<std::uint32_t>(c.spp));
  EXPECT_EQ(run.stats.max_spp, static_cast<std::uint32_t>(c.spp));
  EXPECT_EQ(run.stats.primary_rays, static_cast<std::uint64_t>(c.width * c.height * c.spp));
  EXPECT_GE(run.stats.rays, run.stats.primary_rays);
  const std::size_t tiles = distributed_tiles(s, static_cast<int>(c.ranks.size())).size();
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(total, tiles * static_cast<std::size_t>(c.spp));
  EXPECT_EQ(last_done, total);
  ASSERT_EQ(run.report.ranks.size(), c.ranks.size());
  for (std::size_t r = 0; r < c.ranks.size(); ++r) EXPECT_EQ(run.report.ranks[r].threads, c.ranks[r].threads);
  EXPECT_GE(run.report.units, tiles);
  // Every rank was ready from the start, and a tile is in one unit at a time: with a tile
  // for every unit in flight (three a rank), every rank took work in the first round.
  for (std::size_t r = 1; r < c.ranks.size(); ++r)
    if (tiles >= 3 * c.ranks.size()) {
      EXPECT_GT(run.results[r], 0) << "rank " << r << " rendered nothing";
    }
  EXPECT_GE(run.report.largest_unit, 1);
}

INSTANTIATE_TEST_SUITE_P(
    Dist, MatchesOneProcess,
    ::testing::Values(Case{"Path1Rank", IntegratorKind::Path, ranks({2}), 24, 24, 4, 8, 0},
                      Case{"Path2Ranks", IntegratorKind::Path, ranks({1, 1}), 32, 24, 5, 16, 0},
                      Case{"Path3RanksTile7Shuffled", IntegratorKind::Path, ranks({2, 1, 3}), 30, 26, 4, 7, 5},
                      Case{"Path3RanksOneTile", IntegratorKind::Path, ranks({1, 2, 1}), 24, 24, 6, 64, 9},
                      // Fewer passes than threads: each pass in strips of block rows.
                      Case{"Path2Ranks4ThreadsFewPasses", IntegratorKind::Path, ranks({4, 4}), 40, 40, 2, 32, 3},
                      Case{"Whitted2RanksTile13", IntegratorKind::Whitted, ranks({1, 2}), 40, 32, 3, 13, 0},
                      Case{"Whitted3RanksShuffled", IntegratorKind::Whitted, ranks({1, 1, 1}), 24, 24, 4, 8, 3},
                      Case{"Ao3Ranks", IntegratorKind::Ao, ranks({2, 1, 1}), 24, 24, 5, 6, 0},
                      Case{"Photon2Ranks", IntegratorKind::Photon, ranks({1, 3}), 24, 24, 3, 8, 7}),
    [](const ::testing::TestParamInfo<Case>& c) { return std::string(c.param.name); });

// Stopped by the flag after rank 0 has merged its first results: the stop's checkpoint comes
// at once, the state is one check_render_state accepts, and both render_image and another
// distributed render take it to the uninterrupted image and sums.
TEST(DistributedRender, AStopLeavesAStateThatResumesToTheSameBits) {
  for (const IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const RenderSettings s = settings(32, 32, 6, 8, kind);
    const Reference ref = reference(s);
    for (const unsigned seed : {0u, 4u}) {
      std::atomic<int> stop{0};
      RenderState state;
      RenderControl control;
      control.stop = &stop;
      int checkpoints = 0;
      control.on_checkpoint = [&](const ImageRGB& image, int passes) {
        ++checkpoints;
        EXPECT_EQ(passes, state.passes);
        EXPECT_TRUE(same_bits(image, state.mean()));
        expect_resumable(state, s);
      };
      // 16 tiles; two units per rank before the first result, one more per result taken
      // with it: at most 12 tiles started, so the stop always comes before the end.
      const test::DistributedRun run = distributed(
          s, ranks({1, 1, 2}), state, [&](std::size_t, std::size_t) { stop.store(1); }, control, seed);
      EXPECT_TRUE(run.stats.stopped) << integrator_name(kind) << ", seed " << seed;
      EXPECT_EQ(checkpoints, 1) << "the stop's own checkpoint, and none other";
      expect_resumable(state, s);
      EXPECT_EQ(run.stats.passes, state.passes);
      EXPECT_LT(state.passes, s.spp);
      EXPECT_TRUE(same_bits(run.image, state.mean()));
      EXPECT_EQ(run.stats.min_spp, static_cast<std::uint32_t>(state.passes));

      RenderState by_image = state;
      RenderSettings resume = s;
      resume.threads = 3;
      EXPECT_TRUE(same_bits(one_process(resume, by_image), ref.image)) << integrator_name(kind) << ", seed " << seed;
      EXPECT_TRUE(same_sums(by_image, ref.state));
      RenderState by_ranks = state;
      EXPECT_TRUE(same_bits(distributed(s, ranks({2, 1}), by_ranks, {}, {}, seed + 1).image, ref.image));
      EXPECT_TRUE(same_sums(by_ranks, ref.state));
      EXPECT_EQ(by_ranks.passes, s.spp);
    }
  }
}

// The flag set from a thread of its own once some results are in, as a signal handler
// would: wherever the render was, what it leaves resumes to the same bits.
TEST(DistributedRender, AStopFromAnotherThreadResumes) {
  const RenderSettings s = settings(32, 24, 5, 8);
  const Reference ref = reference(s);
  for (const std::size_t after : {1u, 10u, 30u}) {
    std::atomic<int> stop{0};
    std::atomic<std::size_t> merged{0};
    std::thread stopper([&] {
      while (merged.load() < after) std::this_thread::yield();
      stop.store(1);
    });
    RenderState state;
    RenderControl control;
    control.stop = &stop;
    const test::DistributedRun run =
        distributed(s, ranks({1, 1, 1}), state, [&](std::size_t done, std::size_t) { merged.store(done); }, control);
    stopper.join();
    expect_resumable(state, s);
    EXPECT_TRUE(same_bits(run.image, state.mean()));
    EXPECT_TRUE(same_bits(one_process(s, state), ref.image)) << "stopped after " << after;
    EXPECT_TRUE(same_sums(state, ref.state));
  }
}

// A time limit already past: nothing is handed out, every rank still ends, and the state
// left (nothing) resumes to the full image.
TEST(DistributedRender, AnElapsedTimeLimitStopsAtOnce) {
  const RenderSettings s = settings(24, 24, 3, 8);
  RenderState state;
  RenderControl control;
  control.time_limit_s = 1e-12;
  const test::DistributedRun run = distributed(s, ranks({1, 2}), state, {}, control);
  EXPECT_TRUE(run.stats.stopped);
  EXPECT_EQ(run.report.units, 0u);
  expect_resumable(state, s);
  EXPECT_TRUE(same_bits(one_process(s, state), reference(s).image));
}

// render_image stopped in the middle of a pass (8x8 tiles, some a sample ahead) resumed by
// a distributed render with larger tiles, so its tiles hold pixels at different counts;
// then on to more samples than first asked.
TEST(DistributedRender, ResumesAOneProcessStateStoppedMidPass) {
  RenderSettings s = settings(32, 24, 5, 8);
  s.threads = 1;
  const Reference ref = reference(s);
  std::atomic<int> stop{0};
  RenderState stopped;
  one_process(
      s, stopped,
      [&](std::size_t done, std::size_t) {
        if (done == 12 + 12 + 5) stop.store(1);  // 12 tiles a pass: 2 passes and 5 tiles
      },
      &stop);
  ASSERT_EQ(stopped.passes, 2);
  ASSERT_EQ(std::count(stopped.count.begin(), stopped.count.end(), 3u), 5 * 64);
  for (const int tile_size : {16, 12, 32}) {
    RenderSettings d = s;
    d.tile_size = tile_size;
    RenderState state = stopped;
    const test::DistributedRun run = distributed(d, ranks({1, 2, 1}), state, {}, {}, tile_size);
    EXPECT_TRUE(same_bits(run.image, ref.image)) << "tiles of " << tile_size;
    EXPECT_TRUE(same_sums(state, ref.state));
    EXPECT_EQ(state.passes, s.spp);
    // Every pixel of a tile takes the tile's passes; the merger drops the samples a pixel has.
    EXPECT_GE(run.stats.primary_rays, 32u * 24u * 3u - 5u * 64u);
    EXPECT_LE(run.stats.primary_rays, 32u * 24u * 3u);

    RenderSettings more = d;
    more.spp = 7;
    const test::DistributedRun further = distributed(more, ranks({2, 1}), state);
    EXPECT_TRUE(same_bits(further.image, reference(more).image));
    EXPECT_EQ(further.stats.primary_rays, 32u * 24u * 2u);
  }
}

// A state already at spp: nothing to hand out, every rank still ends, the image is the state's.
TEST(DistributedRender, AFinishedStateRendersNothing) {
  const RenderSettings s = settings(24, 24, 3, 8);
  const Reference ref = reference(s);
  RenderState state = ref.state;
  const test::DistributedRun run = distributed(s, ranks({1, 1}), state);
  EXPECT_TRUE(same_bits(run.image, ref.image));
  EXPECT_TRUE(same_sums(state, ref.state));
  EXPECT_FALSE(run.stats.stopped);
  EXPECT_EQ(run.report.units, 0u);
  EXPECT_EQ(run.stats.primary_rays, 0u);
}

// Checkpoints on the way: each on rank 0's thread with the state so far, which is one a
// render could resume; resumed (the first, a middle and the last) they give the same bits.
TEST(DistributedRender, CheckpointsHandOutResumableStates) {
  const RenderSettings s = settings(24, 24, 8, 8);
  const Reference ref = reference(s);
  RenderState state;
  RenderControl control;
  control.checkpoint_s = 1e-9;
  std::vector<RenderState> saved;
  const std::thread::id rank0 = std::this_thread::get_id();
  control.on_checkpoint = [&](const ImageRGB& image, int passes) {
    EXPECT_EQ(std::this_thread::get_id(), rank0);
    EXPECT_EQ(passes, state.passes);
    EXPECT_LT(passes, s.spp);
    EXPECT_TRUE(same_bits(image, state.mean()));
    expect_resumable(state, s);
    saved.push_back(state);
  };
  const test::DistributedRun run = distributed(s, ranks({1, 1}), state, {}, control);
  EXPECT_TRUE(same_bits(run.image, ref.image));
  ASSERT_FALSE(saved.empty());
  for (const std::size_t k : {std::size_t{0}, saved.size() / 2, saved.size() - 1}) {
    RenderState resumed = saved[k];
    EXPECT_TRUE(same_bits(one_process(s, resumed), ref.image)) << "checkpoint " << k << " of " << saved.size();
    EXPECT_TRUE(same_sums(resumed, ref.state));
  }
}

// The render ends with the worker's error, and what was rendered is saved first (through
// on_checkpoint) as a state a resume can continue.
TEST(DistributedRender, AWorkerThatFailedItsSetupEndsTheRender) {
  const RenderSettings s = settings(24, 24, 3, 8);
  std::vector<RankSetup> r = ranks({1, 1, 1});
  r[2].ok = false;
  r[2].error = "cannot read cornell.gltf: no such file";
  RenderState state;
  int saves = 0;
  RenderControl control;
  control.on_checkpoint = [&](const ImageRGB&, int) {
    ++saves;
    expect_resumable(state, s);
  };
  try {
    distributed(s, r, state, {}, control);
    FAIL() << "no WorkerSetupFailed";
  } catch (const WorkerSetupFailed& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rank 2"), std::string::npos) << what;
    EXPECT_NE(what.find("thread-2"), std::string::npos) << "the host: " << what;
    EXPECT_NE(what.find("cannot read cornell.gltf: no such file"), std::string::npos) << what;
    EXPECT_NE(what.find("--resume"), std::string::npos) << what;
  }
  EXPECT_EQ(saves, 1);
}

// A worker whose facts (scene, settings, version) are not rank 0's would render another
// image: it is refused like a failed setup.
TEST(DistributedRender, AWorkerThatRendersOtherFactsIsRefused) {
  const RenderSettings s = settings(24, 24, 3, 8);
  std::vector<RankSetup> r = ranks({1, 1});
  r[1].facts = "another scene";
  RenderState state;
  try {
    distributed(s, r, state);
    FAIL() << "no WorkerSetupFailed";
  } catch (const WorkerSetupFailed& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rank 1"), std::string::npos) << what;
    EXPECT_NE(what.find("another image than rank 0"), std::string::npos) << what;
  }
}

// The failed worker's Ready comes only after rank 0 has rendered everything itself: the
// image is whole (that worker rendered none of it), so the render ends as one process's
// would, with the failure as a warning.
TEST(DistributedRender, AWorkerThatFailsOnceTheImageIsDoneOnlyWarns) {
  const RenderSettings s = settings(24, 24, 2, 8);
  const Reference ref = reference(s);
  std::atomic<bool> all_merged{false};
  std::vector<RankSetup> r = ranks({2, 1});
  r[1].ok = false;
  r[1].error = "out of memory building the tree";
  r[1].before_ready = [&] {
    while (!all_merged.load()) std::this_thread::yield();
  };
  RenderState state;
  auto progress = [&](std::size_t done, std::size_t total) {
    if (done == total) all_merged.store(true);
  };
  const test::DistributedRun run = distributed(s, r, state, progress);
  EXPECT_TRUE(all_merged.load());
  EXPECT_TRUE(same_bits(run.image, ref.image));
  ASSERT_EQ(run.report.warnings.size(), 1u);
  EXPECT_NE(run.report.warnings[0].find("rank 1"), std::string::npos) << run.report.warnings[0];
  EXPECT_NE(run.report.warnings[0].find("out of memory building the tree"), std::string::npos);
}

// Rank 0 failed its own setup: abandon_distributed stops every worker, failed or not.
TEST(DistributedRender, AbandonEndsEveryWorker) {
  const RenderSettings s = settings(24, 24, 2, 8);
  const test::HangWatchdog watchdog("abandon_distributed");
  const PinholeCamera camera = camera_for(s);
  test::InProcessHub hub(3);
  std::vector<std::thread> workers;
  for (int r = 1; r < 3; ++r)
    workers.emplace_back([&, r] {
      test::InProcessChannel channel(hub, r);
      WorkerReady me;
      if (r == 1) {
        TileRunner runner(1);
        const SampleRenderer renderer(cornell(), accel(), camera, s, runner);
        serve_distributed(channel, &renderer, s, &runner, me);
      } else {
        me.ok = false;
        me.error = "no scene";
        serve_distributed(channel, nullptr, s, nullptr, me);
      }
    });
  test::InProcessChannel channel(hub, 0);
  abandon_distributed(channel);
  for (std::thread& w : workers) w.join();
}

TEST(DistributedRender, TilesAreTheSettingsButNeverLargerThanTheLimit) {
  RenderSettings s = settings(300, 130, 1, 200);
  const std::vector<Tile> tiles = distributed_tiles(s);
  ASSERT_EQ(tiles.size(), 6u);
  EXPECT_EQ(tiles[0].x1 - tiles[0].x0, kMaxDistributedTile);
  EXPECT_EQ(tiles[5].x1, 300);
  EXPECT_EQ(tiles[5].y1, 130);
  s.tile_size = 16;
  EXPECT_EQ(distributed_tiles(s).size(), 19u * 9u);
  // Enough tiles for three units per rank: 171 tiles of 16 serve 57 ranks; 58 need tiles of
  // 8; no tile is smaller than a block, however many ranks.
  EXPECT_EQ(distributed_tiles(s, 57).size(), 19u * 9u);
  EXPECT_EQ(distributed_tiles(s, 58).size(), 38u * 17u);
  EXPECT_EQ(distributed_tiles(settings(24, 24, 1, 64), 4).size(), 9u) << "64 -> 32 -> 16 -> 8";
  EXPECT_EQ(distributed_tiles(settings(24, 24, 1, 64), 1000).size(), 9u);
}

// A unit's sums at `count` samples a pixel, zero sums.
UnitTask task_for(const Tile& tile, const WorkUnit& unit, std::uint32_t count) {
  const auto n = static_cast<std::size_t>((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
  return {unit, TileSums{std::vector<glm::dvec3>(n, glm::dvec3(0.0)), std::vector<std::uint32_t>(n, count)}};
}

// A unit asked to stop before it starts returns no pass and its sums as they were; a unit
// adds each pass only to the pixels at that many samples; a unit for no tile, or whose sums
// do not fit its tile, is refused.
TEST(LocalWorker, StopsAddsInOrderAndRefusesUnitsThatDoNotFit) {
  const RenderSettings s = settings(24, 24, 4, 8);
  TileRunner runner(1);
  const PinholeCamera camera = camera_for(s);
  const SampleRenderer renderer(cornell(), accel(), camera, s, runner);
  const std::vector<Tile> tiles = distributed_tiles(s);
  const std::atomic<bool> stopped{true};
  const UnitResult none = render_unit(renderer, tiles[0], task_for(tiles[0], WorkUnit{0, 0, 0, 3}, 0), runner, stopped);
  EXPECT_EQ(none.passes_done, 0);
  for (std::uint32_t c : none.sums.count) EXPECT_EQ(c, 0u);
  const std::atomic<bool> go{false};
  const UnitResult all = render_unit(renderer, tiles[1], task_for(tiles[1], WorkUnit{1, 1, 1, 3}, 1), runner, go);
  EXPECT_EQ(all.passes_done, 3);
  ASSERT_EQ(all.sums.count.size(), 64u);
  for (std::uint32_t c : all.sums.count) EXPECT_EQ(c, 4u);
  EXPECT_EQ(all.primary_rays, 3u * 64u);
  // Pixels at 0 samples cannot take pass 1: the unit leaves them alone.
  const UnitResult behind = render_unit(renderer, tiles[1], task_for(tiles[1], WorkUnit{2, 1, 1, 3}, 0), runner, go);
  for (std::uint32_t c : behind.sums.count) EXPECT_EQ(c, 0u);
  UnitTask wrong = task_for(tiles[0], WorkUnit{3, 0, 0, 1}, 0);
  wrong.sums.sum.pop_back();
  EXPECT_THROW(render_unit(renderer, tiles[0], wrong, runner, go), std::invalid_argument);
  LocalWorker worker(renderer, tiles, runner, 1);
  EXPECT_THROW(worker.push(task_for(tiles[0], WorkUnit{4, static_cast<std::uint32_t>(tiles.size()), 0, 1}, 0)),
               std::invalid_argument);
}

}  // namespace
}  // namespace lancer
