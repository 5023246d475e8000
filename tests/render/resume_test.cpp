// Resuming a render (RenderControl::state): a render continued from the state a checkpoint
// or a stop left, even one in the middle of a pass or with pixels passes apart (as a
// distributed render leaves them), ends with the uninterrupted render's image bit for bit,
// for any thread count; and that state survives its EXR file exactly
// (render/checkpoint_file.h), while a plain, damaged or truncated file is refused.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/checkpoint_file.h"
#include "render/image_io.h"
#include "render/renderer.h"
#include "render/tile_scheduler.h"
#include "scene/load_scene.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

const Scene& cornell() {
  static const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  return scene;
}

const KdTree& tree() {
  static const KdTree kd(cornell().triangles);
  return kd;
}

RenderSettings settings(int spp, int threads, IntegratorKind integrator = IntegratorKind::Path) {
  RenderSettings s;
  s.width = 24;
  s.height = 20;
  s.spp = spp;
  s.threads = threads;
  s.tile_size = 8;  // 3 x 3 tiles of one 8x8 block each
  s.seed = 3;
  s.integrator = integrator;
  return s;
}
constexpr std::size_t kTiles = 9;
constexpr std::size_t kPixels = 24 * 20;

bool same_bits(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

bool same_sums(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  // An empty vector's data() may be null, which memcmp must not be given.
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::dvec3)) == 0);
}

// Every field, the light tracer's sums included.
bool same_state(const RenderState& a, const RenderState& b) {
  return a.width == b.width && a.height == b.height && a.passes == b.passes && a.count == b.count &&
         same_sums(a.sum, b.sum) && a.light_passes == b.light_passes && a.light_paths == b.light_paths &&
         same_sums(a.light, b.light) && same_sums(a.pending, b.pending);
}

ImageRGB render(const RenderSettings& s, RenderStats& stats, const ProgressCallback& p = {},
                const RenderControl& c = {}) {
  const PinholeCamera cam = PinholeCamera::from_desc(cornell().cameras.at(0), s.width, s.height);
  return render_image(cornell(), tree(), cam, s, stats, p, c);
}

// Renders `s` into `full` and `image`, keeping the state after each pass but the last (a
// checkpoint after every pass).
std::vector<RenderState> states_after_each_pass(const RenderSettings& s, RenderState& full, ImageRGB& image) {
  std::vector<RenderState> after;
  RenderControl control;
  control.state = &full;
  control.checkpoint_s = 1e-9;
  control.on_checkpoint = [&](const ImageRGB&, int) { after.push_back(full); };
  RenderStats stats;
  image = render(s, stats, {}, control);
  return after;
}

ImageRGB render_from(RenderState& state, const RenderSettings& s, RenderStats& stats) {
  RenderControl control;
  control.state = &state;
  return render(s, stats, {}, control);
}

// The state a render of `s` leaves when the stop flag is set after `tiles` tiles (one thread).
RenderState stopped_after(const RenderSettings& s, std::size_t tiles) {
  std::atomic<int> stop{0};
  RenderState state;
  RenderControl control;
  control.stop = &stop;
  control.state = &state;
  RenderStats stats;
  render(
      s, stats,
      [&](std::size_t done, std::size_t) {
        if (done == tiles) stop.store(2);
      },
      control);
  EXPECT_TRUE(stats.stopped);
  return state;
}

TEST(Resume, FromEachCheckpointGivesTheUninterruptedImage) {
  std::vector<RenderState> saved;
  RenderState state;
  RenderControl control;
  control.state = &state;
  control.checkpoint_s = 1e-9;  // after every pass but the last
  control.on_checkpoint = [&](const ImageRGB& image, int passes) {
    EXPECT_EQ(state.passes, passes);
    EXPECT_TRUE(same_bits(image, state.mean()));
    saved.push_back(state);
  };
  RenderStats stats;
  const ImageRGB full = render(settings(5, 2), stats, {}, control);
  ASSERT_EQ(saved.size(), 4u);
  EXPECT_EQ(state.passes, 5);
  for (std::size_t k = 0; k < saved.size(); ++k) {
    for (const int threads : {1, 3}) {
      RenderState resumed = saved[k];
      RenderStats st;
      EXPECT_TRUE(same_bits(full, render_from(resumed, settings(5, threads), st)))
          << "from the checkpoint after " << k + 1 << " passes, " << threads << " threads";
      EXPECT_TRUE(same_state(resumed, state));
      EXPECT_EQ(st.passes, 5);
      EXPECT_EQ(st.primary_rays, kPixels * (4 - k)) << "only the missing passes are rendered";
    }
  }
}

// Stopped after 2 passes and 4 tiles of the third: the first resumed pass renders only the
// 5 tiles that still lack their third sample, and the image is the uninterrupted one.
TEST(Resume, AfterAStopMidPassGivesTheUninterruptedImage) {
  RenderStats straight_stats;
  const ImageRGB straight = render(settings(6, 2), straight_stats);
  RenderState state = stopped_after(settings(6, 1), 2 * kTiles + 4);
  ASSERT_EQ(state.passes, 2);
  std::size_t ahead = 0;
  for (std::uint32_t c : state.count) ahead += c == 3;
  ASSERT_EQ(ahead, 4u * 64u) << "four 8x8 tiles have their third sample";
  for (const int threads : {1, 2, 4}) {
    RenderState resumed = state;
    RenderStats st;
    EXPECT_TRUE(same_bits(straight, render_from(resumed, settings(6, threads), st))) << threads << " threads";
    EXPECT_EQ(st.primary_rays, kPixels * 4 - ahead);
    EXPECT_EQ(st.min_spp, 6u);
    EXPECT_EQ(st.max_spp, 6u);
  }
}

// Stopped twice, the second time in the first resumed pass, then finished with more
// samples than first asked: still the straight render's image.
TEST(Resume, TwiceAndToMoreSamples) {
  RenderStats straight_stats;
  const ImageRGB straight = render(settings(7, 2), straight_stats);
  RenderState state = stopped_after(settings(4, 1), kTiles + 3);
  std::atomic<int> stop{0};
  RenderControl control;
  control.stop = &stop;
  control.state = &state;
  RenderStats stats;
  render(
      settings(4, 1), stats,
      [&](std::size_t done, std::size_t) {
        if (done == 2) stop.store(2);  // in pass 1, which 3 tiles had already
      },
      control);
  EXPECT_EQ(state.passes, 1);
  RenderStats st;
  EXPECT_TRUE(same_bits(straight, render_from(state, settings(7, 2), st)));
}

// Every integrator of the common loop resumes the same way (the debug views for free).
TEST(Resume, EveryIntegratorOfTheCommonLoop) {
  for (const IntegratorKind kind : {IntegratorKind::Whitted, IntegratorKind::Ao, IntegratorKind::Normals,
                                    IntegratorKind::Depth, IntegratorKind::Albedo, IntegratorKind::PrimId}) {
    RenderStats straight_stats;
    const ImageRGB straight = render(settings(3, 2, kind), straight_stats);
    RenderState state = stopped_after(settings(3, 1, kind), kTiles + 5);
    RenderStats st;
    EXPECT_TRUE(same_bits(straight, render_from(state, settings(3, 2, kind), st))) << integrator_name(kind);
  }
}

// A distributed render stopped early leaves its tiles passes apart (dist/pass_scheduler.h):
// a state whose pixels have any counts within [passes, spp], pieced together here from
// the checkpoints of one render, is accepted and resumed to the uninterrupted image, each
// pixel adding only the samples it lacks.
TEST(Resume, PixelsAtAnyCountsBetweenPassesAndSpp) {
  RenderState full;
  ImageRGB straight;
  std::vector<RenderState> after = states_after_each_pass(settings(6, 2), full, straight);  // [k]: after k + 1
  after.insert(after.begin(), RenderState{});
  after.front().reset(24, 20);
  after.push_back(full);
  ASSERT_EQ(after.size(), 7u);

  // Per 8x8 tile of the 24x20 image: 1 to 6 samples; some pixels a sample or two ahead.
  RenderState pieced;
  pieced.reset(24, 20);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 24; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 24 + static_cast<std::size_t>(x);
      int k = 1 + (x / 8 + 3 * (y / 8)) % 6;
      if (x % 5 == 0 && y % 3 == 0) k = std::min(6, k + 1 + (x + y) % 2);
      pieced.sum[p] = after[static_cast<std::size_t>(k)].sum[p];
      pieced.count[p] = after[static_cast<std::size_t>(k)].count[p];
      ASSERT_EQ(pieced.count[p], static_cast<std::uint32_t>(k));
    }
  // Camera rays go by 8x8 block (here a tile): a block takes pass s when a pixel lacks sample s.
  std::uint64_t traced = 0;
  for (const Tile& tile : make_tiles(24, 20, 8)) {
    std::uint32_t least = 6;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x)
        least = std::min(least, pieced.count[static_cast<std::size_t>(y) * 24 + static_cast<std::size_t>(x)]);
    traced += (6 - least) * static_cast<std::uint64_t>((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
  }
  pieced.passes = 1;
  // The light tracer's sums are the image's, not a pixel's: a distributed render leaves them
  // at least as far as its full passes (here 3 of 6).
  pieced.light = after[3].light;
  pieced.light_passes = after[3].light_passes;
  pieced.light_paths = after[3].light_paths;
  ASSERT_EQ(pieced.light_passes, 3);
  EXPECT_NO_THROW(check_render_state(pieced, settings(6, 1)));
  EXPECT_NO_THROW(check_render_state(pieced, settings(9, 1))) << "resumed to more samples";
  EXPECT_THROW(check_render_state(pieced, settings(5, 1)), std::invalid_argument) << "pixels beyond spp";
  RenderState later = pieced;
  later.passes = 2;
  EXPECT_THROW(check_render_state(later, settings(6, 1)), std::invalid_argument) << "pixels short of passes";
  for (const int threads : {1, 3}) {
    RenderState resumed = pieced;
    RenderStats st;
    EXPECT_TRUE(same_bits(straight, render_from(resumed, settings(6, threads), st))) << threads << " threads";
    EXPECT_TRUE(same_state(resumed, full));
    EXPECT_EQ(st.primary_rays, traced) << "only the blocks that lack a sample";
    EXPECT_EQ(st.min_spp, 6u);
  }
}

// A distributed render's rank 0 may save a state whose light passes (render/light_tracer.h)
// lag its samples: they do not depend on the samples, so resuming traces the missing ones,
// in order, and ends with the uninterrupted render's image and sums.
TEST(Resume, LightPassesBehindTheSamplesAreTracedOnResuming) {
  RenderState full;
  ImageRGB straight;
  const std::vector<RenderState> after = states_after_each_pass(settings(4, 2), full, straight);  // [k]: after k + 1
  ASSERT_EQ(after.size(), 3u);
  RenderState lagging = after[2];
  lagging.light = after[0].light;
  lagging.light_passes = after[0].light_passes;
  ASSERT_EQ(lagging.passes, 3);
  ASSERT_EQ(lagging.light_passes, 1);
  RenderStats st;
  EXPECT_TRUE(same_bits(straight, render_from(lagging, settings(4, 1), st)));
  EXPECT_TRUE(same_state(lagging, full));
  // Also once every sample is there.
  RenderState done = full;
  done.light = after[0].light;
  done.light_passes = after[0].light_passes;
  EXPECT_TRUE(same_bits(straight, render_from(done, settings(4, 1), st)));
  EXPECT_TRUE(same_state(done, full));
}

TEST(Resume, RefusesAStateItCouldNotHaveLeft) {
  RenderState state = stopped_after(settings(4, 1), kTiles + 2);
  RenderStats st;
  {
    RenderState other_size = state;
    other_size.width = 20;
    EXPECT_THROW(render_from(other_size, settings(4, 1), st), std::invalid_argument);
  }
  {
    RenderState behind = state;
    behind.count[0] = 0;  // short of the pass it says every pixel had
    EXPECT_THROW(render_from(behind, settings(4, 1), st), std::invalid_argument);
  }
  {
    RenderState beyond = state;
    beyond.count[0] = 5;  // more than spp
    EXPECT_THROW(render_from(beyond, settings(4, 1), st), std::invalid_argument);
  }
  {
    RenderState more_than_asked = state;  // 1 pass, some pixels at 2
    EXPECT_THROW(render_from(more_than_asked, settings(1, 1), st), std::invalid_argument);
  }
  RenderControl sppm;
  sppm.state = &state;
  EXPECT_THROW(render(settings(2, 1, IntegratorKind::Sppm), st, {}, sppm), std::invalid_argument);
}

class CheckpointFile : public ::testing::Test {
 protected:
  static std::string bytes_of(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write_bytes(const fs::path& f, const std::string& bytes) {
    std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes;
  }

  test::TempDir temp_{"lancer_checkpoint"};
  const fs::path& dir_ = temp_.path();
  const CheckpointFacts facts_ = {{"seed", "3"}, {"width", "24"}, {"scene", "0123456789abcdef"}};
};

// The sums go through the file bit for bit (they are doubles; the picture is only floats),
// and a resume from the file read back gives the straight image.
TEST_F(CheckpointFile, KeepsTheStateExactly) {
  const RenderState state = stopped_after(settings(3, 1), kTiles + 4);
  const fs::path file = dir_ / "state.exr";
  write_checkpoint(state, facts_, file);
  Checkpoint cp = read_checkpoint(file);
  EXPECT_TRUE(same_state(cp.state, state));
  CheckpointFacts sorted = facts_;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(cp.facts, sorted);
  EXPECT_TRUE(same_bits(read_image(file), state.mean())) << "viewers see the image so far";
  RenderStats a, b;
  EXPECT_TRUE(same_bits(render(settings(3, 2), a), render_from(cp.state, settings(3, 2), b)));
}

TEST_F(CheckpointFile, RefusesAFileWithoutResumeData) {
  const fs::path file = dir_ / "plain.exr";
  write_image(stopped_after(settings(3, 1), 4).mean(), file);
  try {
    read_checkpoint(file);
    FAIL() << "a plain EXR was read as a checkpoint";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("has no resume data"), std::string::npos) << e.what();
  }
  write_image(stopped_after(settings(3, 1), 4).mean(), dir_ / "plain.png");
  EXPECT_THROW(read_checkpoint(dir_ / "plain.png"), ImageError);
}

// One character of a fact changed in the file's bytes (EXR headers have no checksum of
// their own), the file cut short, a channel left out: each refused, none resumed.
TEST_F(CheckpointFile, RefusesADamagedFile) {
  const RenderState state = stopped_after(settings(3, 1), kTiles + 4);
  const fs::path file = dir_ / "state.exr";
  write_checkpoint(state, facts_, file);
  const std::string good = bytes_of(file);

  std::string edited = good;
  const std::size_t at = edited.find("0123456789abcdef");
  ASSERT_NE(at, std::string::npos);
  edited[at + 3] = 'x';
  write_bytes(file, edited);
  try {
    read_checkpoint(file);
    FAIL() << "an edited attribute went unnoticed";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("digest"), std::string::npos) << e.what();
  }

  std::string passes = good;  // the int attribute's value: name, type "int", size 4, value
  const std::string key = std::string("lancer.passes") + '\0' + "int" + '\0';
  const std::size_t p = passes.find(key);
  ASSERT_NE(p, std::string::npos);
  passes[p + key.size() + 4] ^= 1;
  write_bytes(file, passes);
  EXPECT_THROW(read_checkpoint(file), ImageError);

  write_bytes(file, good.substr(0, good.size() / 2));
  EXPECT_THROW(read_checkpoint(file), ImageError);
  write_bytes(file, good.substr(0, 200));  // inside the header
  EXPECT_THROW(read_checkpoint(file), ImageError);

  write_bytes(file, good);
  ExrExtras extras;
  const ImageRGB image = read_exr(file, extras, "lancer.");
  std::erase_if(extras.uint_channels, [](const auto& c) { return c.first == "lancer.count"; });
  write_exr(image, file, extras);
  try {
    read_checkpoint(file);
    FAIL() << "a missing channel went unnoticed";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("lancer.count"), std::string::npos) << e.what();
  }
}

// The light tracer's sums (render/light_tracer.h: this scene's spheres have them, and a stop
// mid-pass leaves a pending pass): every attribute and channel of them accounted for, or the
// file is refused.
TEST_F(CheckpointFile, RefusesDamagedLightSums) {
  const RenderState state = stopped_after(settings(3, 1), kTiles + 4);
  ASSERT_GT(state.light_passes, 0);
  ASSERT_FALSE(state.pending.empty());
  const fs::path file = dir_ / "state.exr";
  write_checkpoint(state, facts_, file);
  ExrExtras good;
  const ImageRGB image = read_exr(file, good, "lancer.");
  auto expect_refused = [&](const ExrExtras& extras, const std::string& what) {
    write_exr(image, file, extras);
    EXPECT_THROW(read_checkpoint(file), ImageError) << what;
  };
  for (const char* attribute : {"lancer.lightPasses", "lancer.lightPaths", "lancer.lightPending"}) {
    ExrExtras e = good;
    std::erase_if(e.ints, [&](const auto& i) { return i.first == attribute; });
    expect_refused(e, std::string("without ") + attribute);
  }
  for (const char* channel : {"lancer.lightHi.G", "lancer.pendingLo.B"}) {
    ExrExtras e = good;
    std::erase_if(e.uint_channels, [&](const auto& c) { return c.first == channel; });
    expect_refused(e, std::string("without ") + channel);
  }
  for (const auto& [name, value] : std::vector<std::pair<std::string, int>>{
           {"lancer.lightPasses", 0}, {"lancer.lightPasses", -1}, {"lancer.lightPaths", 0}, {"lancer.lightPending", 2}}) {
    ExrExtras e = good;
    for (auto& i : e.ints)
      if (i.first == name) i.second = value;
    expect_refused(e, name + " = " + std::to_string(value));
  }
  ExrExtras no_pending = good;  // the pending pass's channels left behind
  for (auto& i : no_pending.ints)
    if (i.first == "lancer.lightPending") i.second = 0;
  expect_refused(no_pending, "pending channels with lightPending = 0");
  write_checkpoint(state, facts_, file);
  EXPECT_NO_THROW(read_checkpoint(file));
}

// A file that asks for hundreds of full-image integer channels (each a full image of memory
// when read) is refused before they are allocated.
TEST_F(CheckpointFile, RefusesAFileWithTooManyChannels) {
  const RenderState state = stopped_after(settings(3, 1), 4);
  const fs::path file = dir_ / "many.exr";
  ExrExtras extras;
  for (std::size_t i = 0; i <= kMaxExrExtraChannels; ++i)
    extras.uint_channels.emplace_back("lancer.x" + std::to_string(i), std::vector<std::uint32_t>(state.pixels()));
  write_exr(state.mean(), file, extras);
  try {
    read_checkpoint(file);
    FAIL() << "read";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("integer channels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lancer
