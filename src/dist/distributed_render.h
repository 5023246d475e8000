// A render spread over the ranks of a Channel (processes on one or many machines): every
// rank has loaded the scene, built its tree and made the same SampleRenderer; rank 0 hands
// out work units (passes over a tile, with the tile's sums: TileQueue) on demand and renders
// some itself; each rank adds a unit's samples in one process's order (render_unit), so the
// image is the one a single process gives, bit for bit, for any number of ranks and threads.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "dist/channel.h"
#include "render/image.h"
#include "render/render_control.h"
#include "render/render_settings.h"
#include "render/renderer.h"
#include "render/sample_renderer.h"
#include "render/tile_scheduler.h"

namespace lancer {

// What a worker tells rank 0 once its setup is over.
struct WorkerReady {
  bool ok = true;
  int threads = 1;
  double load_s = 0.0, build_s = 0.0;  // reading the scene, building the tree
  std::string host;
  std::string error;  // when !ok
  // A digest of what the rank renders (scene files and their contents, every setting that
  // changes the image, the program version): rank 0 refuses a worker whose digest is not
  // its own, for its samples would belong to another image.
  std::string facts;
};
std::vector<std::byte> pack(const WorkerReady& ready);
WorkerReady unpack_ready(const std::vector<std::byte>& bytes);

// Tiles of a distributed render over `ranks` ranks: settings.tile_size, at most
// kMaxDistributedTile on a side so that a unit stays a modest message, and halved (down to
// one 8x8 block) while the image has fewer tiles than the units `ranks` ranks hold at once,
// so that every rank has work. Every rank computes the same; the tile size never changes
// the image.
inline constexpr int kMaxDistributedTile = 128;
inline constexpr int kUnitsInFlight = 3;  // per rank: one in hand, two waiting
std::vector<Tile> distributed_tiles(const RenderSettings& settings, int ranks = 1);

// A worker could not set up (its message names the rank, the host and why); every rank has
// been told to stop and has answered.
class WorkerSetupFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What rank 0 learnt about the render beside RenderStats.
struct DistributedReport {
  std::vector<WorkerReady> ranks;  // [0] is rank 0's own
  std::size_t units = 0;           // units handed out
  int largest_unit = 0;            // most passes in one unit
  // Workers that failed their setup after the work was done (the image is whole).
  std::vector<std::string> warnings;
};

// Rank 0. `state` as render_image's RenderControl::state (empty: a fresh render; otherwise
// checked with check_render_state). control: stop flag and time limit as render_image; on a
// stop by the flag, on_checkpoint is called with the image so far at once (the runtime
// kills every rank soon after a signal), then once the workers have answered the stop, the
// function returns. control.checkpoint_s: on_checkpoint every so many seconds. `me` is rank
// 0's own setup. Throws WorkerSetupFailed when a worker failed its setup or renders other
// facts than rank 0 (after saving the image so far through on_checkpoint).
ImageRGB render_distributed(Channel& channel, const SampleRenderer& renderer, const RenderSettings& settings,
                            TileRunner& runner, const WorkerReady& me, RenderState& state, RenderStats& stats,
                            DistributedReport& report, const ProgressCallback& progress = {},
                            const RenderControl& control = {});

// Ranks 1..n-1: sends `me` (Ready), then renders the units rank 0 sends until it says Stop.
// A worker whose setup failed (me.ok false) sends that and waits for the Stop.
void serve_distributed(Channel& channel, const SampleRenderer* renderer, const RenderSettings& settings,
                       TileRunner* runner, const WorkerReady& me);

// Rank 0 when its own setup failed: tells every worker to stop and waits for them.
void abandon_distributed(Channel& channel);

}  // namespace lancer
