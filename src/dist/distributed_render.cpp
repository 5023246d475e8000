#include "dist/distributed_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "dist/local_worker.h"
#include "dist/tile_queue.h"
#include "dist/work_unit.h"
#include "render/primary_block.h"

namespace lancer {

namespace {

using Clock = std::chrono::steady_clock;

// A unit's aim, in wall seconds on its rank: long enough that messages cost nothing beside
// it, short enough that the last units end together (the render's tail).
constexpr double kUnitSeconds = 0.1;
// A unit takes a tile at most 1/kSpreadDivisor of the passes every pixel has ahead of the
// least advanced, so a render stopped early (by a time limit, say) has nearly as many
// samples in every tile; but never less than kShortestUnitSeconds of work, which keeps the
// ranks busy while the first passes are short.
constexpr int kSpreadDivisor = 8;
constexpr double kShortestUnitSeconds = 0.01;
// How long an idle rank waits for a local result before it polls the channel again.
constexpr std::chrono::microseconds kPoll{2000};

void put_string(std::vector<std::byte>& bytes, const std::string& s) {
  const auto n = static_cast<std::uint32_t>(s.size());
  const std::size_t at = bytes.size();
  bytes.resize(at + sizeof n + s.size());
  std::memcpy(bytes.data() + at, &n, sizeof n);
  std::memcpy(bytes.data() + at + sizeof n, s.data(), s.size());
}

std::string get_string(const std::vector<std::byte>& bytes, std::size_t& at) {
  std::uint32_t n = 0;
  if (bytes.size() - at < sizeof n) throw std::runtime_error("distributed render: a Ready message cut short");
  std::memcpy(&n, bytes.data() + at, sizeof n);
  at += sizeof n;
  if (bytes.size() - at < n) throw std::runtime_error("distributed render: a Ready message cut short");
  std::string s(reinterpret_cast<const char*>(bytes.data() + at), n);
  at += n;
  return s;
}

struct ReadyHeader {
  std::int32_t ok, threads;
  double load_s, build_s;
};

}  // namespace

std::vector<std::byte> pack(const WorkerReady& r) {
  const ReadyHeader h{r.ok ? 1 : 0, r.threads, r.load_s, r.build_s};
  std::vector<std::byte> bytes(sizeof h);
  std::memcpy(bytes.data(), &h, sizeof h);
  put_string(bytes, r.host);
  put_string(bytes, r.error);
  put_string(bytes, r.facts);
  return bytes;
}

WorkerReady unpack_ready(const std::vector<std::byte>& bytes) {
  ReadyHeader h;
  if (bytes.size() < sizeof h) throw std::runtime_error("distributed render: a Ready message cut short");
  std::memcpy(&h, bytes.data(), sizeof h);
  WorkerReady r;
  r.ok = h.ok != 0, r.threads = std::max(h.threads, 1), r.load_s = h.load_s, r.build_s = h.build_s;
  std::size_t at = sizeof h;
  r.host = get_string(bytes, at);
  r.error = get_string(bytes, at);
  r.facts = get_string(bytes, at);
  if (at != bytes.size()) throw std::runtime_error("distributed render: a Ready message with bytes after its end");
  return r;
}

std::vector<Tile> distributed_tiles(const RenderSettings& settings, int ranks) {
  int side = std::min(settings.tile_size, kMaxDistributedTile);
  const auto wanted = static_cast<std::size_t>(kUnitsInFlight) * static_cast<std::size_t>(std::max(ranks, 1));
  std::vector<Tile> tiles = make_tiles(settings.width, settings.height, side);
  while (tiles.size() < wanted && side > kBlockSide) {
    side = std::max(side / 2, kBlockSide);
    tiles = make_tiles(settings.width, settings.height, side);
  }
  return tiles;
}

ImageRGB render_distributed(Channel& channel, const SampleRenderer& renderer, const RenderSettings& settings,
                            TileRunner& runner, const WorkerReady& me, RenderState& state, RenderStats& stats,
                            DistributedReport& report, const ProgressCallback& progress, const RenderControl& control) {
  const auto start = Clock::now();
  const bool timed = control.time_limit_s > 0.0;
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(timed ? control.time_limit_s : 0.0));
  if (state.empty()) state.reset(settings.width, settings.height);
  check_render_state(state, settings);
  check_light_state(state, renderer.light_paths_per_pass());
  const std::vector<Tile> tiles = distributed_tiles(settings, channel.size());
  TileQueue queue(tiles, state, settings.spp);
  LocalWorker local(renderer, tiles, runner, me.threads);

  const int ranks = channel.size();
  report = {};
  report.ranks.assign(static_cast<std::size_t>(ranks), WorkerReady{});
  report.ranks[0] = me;
  // Per rank: ready to take units, units in flight, finished (Done received).
  std::vector<char> ready(static_cast<std::size_t>(ranks), 0), done(static_cast<std::size_t>(ranks), 0);
  std::vector<int> in_flight(static_cast<std::size_t>(ranks), 0);
  ready[0] = 1;
  std::string failure;  // a worker's failed setup

  // Thread-seconds per pixel sample, from the units so far (0: none yet).
  double sample_cost = 0.0;
  const std::size_t tile_pixels = static_cast<std::size_t>(tiles.front().x1 - tiles.front().x0) *
                                  static_cast<std::size_t>(tiles.front().y1 - tiles.front().y0);
  // Passes per thread: about kUnitSeconds of work, unless that spreads the tiles too far.
  auto unit_passes = [&](int threads) {
    long k = 1;
    if (sample_cost > 0.0) {
      const double tile_pass_s = sample_cost * static_cast<double>(tile_pixels);  // one thread's
      auto passes_in = [&](double seconds) {  // (clamped before rounding: a cost may be tiny)
        return std::lround(std::clamp(seconds / tile_pass_s, 1.0, double{kMaxUnitPasses}));
      };
      k = std::min(passes_in(kUnitSeconds), std::max<long>(passes_in(kShortestUnitSeconds),
                                                           queue.least_pass() / kSpreadDivisor));
    }
    const auto by_bytes = static_cast<long>(std::max<std::size_t>(1, kMaxUnitBytes / (tile_pixels * sizeof(glm::vec3))));
    return static_cast<int>(std::clamp(threads * k, 1L, std::min(by_bytes, long{kMaxUnitPasses})));
  };

  bool stopping = false;
  auto hand_out = [&](int rank) {
    while (!stopping && ready[rank] && !done[rank] && in_flight[rank] < kUnitsInFlight) {
      std::optional<UnitTask> task = queue.next(unit_passes(report.ranks[rank].threads));
      if (!task) return;
      ++report.units;
      report.largest_unit = std::max(report.largest_unit, task->unit.passes);
      if (rank == 0) local.push(std::move(*task));
      else channel.send(rank, MessageKind::Unit, pack(*task));
      ++in_flight[rank];
    }
  };
  std::uint64_t rays = renderer.setup_rays(), primary_rays = 0;
  double primary_seconds = 0.0;
  auto take = [&](int rank, UnitResult r) {
    --in_flight[rank];
    rays += r.rays, primary_rays += r.primary_rays, primary_seconds += r.primary_seconds;
    const double samples = static_cast<double>(r.passes_done) * static_cast<double>(r.sums.sum.size());
    if (samples > 0.0 && r.seconds > 0.0) {
      const double cost = r.seconds * std::min(r.threads, r.passes_done) / samples;
      sample_cost = sample_cost > 0.0 ? 0.5 * (sample_cost + cost) : cost;
    }
    queue.finish(r);
    if (progress) progress(static_cast<std::size_t>(queue.tile_passes_done()),
                           static_cast<std::size_t>(queue.total_tile_passes()));
  };
  // Everything that has arrived, from the local worker and the channel; true if anything did.
  auto poll = [&] {
    bool any = false;
    while (std::optional<UnitResult> r = local.take_result()) take(0, std::move(*r)), any = true;
    while (std::optional<Message> m = channel.receive()) {
      any = true;
      const int from = m->from;
      if (from <= 0 || from >= ranks) throw std::runtime_error("distributed render: a message from rank " +
                                                               std::to_string(from));
      switch (m->kind) {
        case MessageKind::Ready: {
          WorkerReady w = unpack_ready(m->bytes);
          if (w.ok && w.facts != me.facts) {
            w.ok = false;
            w.error = "it renders another image than rank 0 (another scene file, scene contents, option or lancer "
                      "version): every machine needs the same lancer, scene files and options";
          }
          if (!w.ok && failure.empty())
            failure = "rank " + std::to_string(from) + " on " + w.host + ": " + w.error;
          ready[from] = w.ok ? 1 : 0;
          report.ranks[from] = std::move(w);
          break;
        }
        case MessageKind::Result: take(from, unpack_result(m->bytes)); break;
        case MessageKind::Done: done[from] = 1, ready[from] = 0; break;
        default: throw std::runtime_error("distributed render: rank " + std::to_string(from) + " sent rank 0 a " +
                                          std::to_string(static_cast<int>(m->kind)));
      }
    }
    return any;
  };

  auto last_checkpoint = start;
  auto interrupted = [&] { return control.stop && control.stop->load(std::memory_order_relaxed) != 0; };
  // The light tracer's passes (render/light_tracer.h) are rank 0's, one per turn of the
  // loop while the workers sample; their sums do not depend on who traced them.
  const auto never = [] { return false; };
  // Light pass 0 before any sample (check_light_state tells a state by it).
  std::uint64_t light_rays = complete_light_passes(renderer, state, std::min(1, settings.spp), never);
  while (!queue.complete()) {
    if (interrupted() || (timed && Clock::now() >= deadline) || !failure.empty()) break;
    const bool any = poll();
    for (int rank = 0; rank < ranks; ++rank) hand_out(rank);
    light_rays += complete_light_passes(renderer, state, std::min(state.light_passes + 1, settings.spp), never);
    if (control.checkpoint_s > 0.0 && control.on_checkpoint && !queue.complete() &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= control.checkpoint_s) {
      queue.settle_passes();
      control.on_checkpoint(state.mean(), state.passes);
      last_checkpoint = Clock::now();
    }
    if (!any) local.wait_for_result(kPoll);
  }
  stopping = true;
  const bool failed = !failure.empty();  // a worker that fails once the work is done only warns
  stats.stopped = !queue.complete();
  // Stop everyone (cheap: a message each and a flag), then take what they finish.
  for (int rank = 1; rank < ranks; ++rank) channel.send(rank, MessageKind::Stop, {});
  local.request_stop();
  // A signal, now or while the others answer: mpirun ends every rank about a second after
  // it, so save what is here at once, while the others wind down.
  bool saved = false;
  auto save_if_signalled = [&] {
    if (saved || !interrupted() || !control.on_checkpoint) return;
    queue.settle_passes();
    control.on_checkpoint(state.mean(), state.passes);
    saved = true;
  };
  save_if_signalled();
  local.stop();
  for (;;) {
    const bool any = poll();
    if (std::count(done.begin() + 1, done.end(), 1) == ranks - 1) break;
    save_if_signalled();
    if (!any) local.wait_for_result(kPoll);
  }
  poll();
  channel.flush();
  if (failed) {
    // What the others rendered is not lost: the outputs hold it, ready for --resume.
    if (control.on_checkpoint) {
      queue.settle_passes();
      control.on_checkpoint(state.mean(), state.passes);
    }
    throw WorkerSetupFailed(failure + (control.on_checkpoint ? " (the image so far is saved: --resume continues it)" : ""));
  }
  if (!failure.empty()) report.warnings.push_back(failure);

  queue.settle_passes();
  // All the light passes once the samples are all there (a stopped render's resume traces
  // any it lacks).
  if (queue.complete()) light_rays += complete_light_passes(renderer, state, settings.spp, never);
  stats.passes = state.passes;
  const auto [lo, hi] = std::minmax_element(state.count.begin(), state.count.end());
  stats.min_spp = *lo;
  stats.max_spp = *hi;
  const std::uint32_t least = *lo;
  stats.pixels_past_min_spp = static_cast<std::size_t>(
      std::count_if(state.count.begin(), state.count.end(), [least](std::uint32_t c) { return c > least; }));
  stats.rays = rays + light_rays;
  stats.light_rays = light_rays;
  stats.primary_rays = primary_rays;
  stats.setup_rays = renderer.setup_rays();
  stats.primary_seconds = primary_seconds;
  stats.path_batches = renderer.path_batches();
  ImageRGB image = state.mean();
  stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return image;
}

void serve_distributed(Channel& channel, const SampleRenderer* renderer, const RenderSettings& settings,
                       TileRunner* runner, const WorkerReady& me) {
  channel.send(0, MessageKind::Ready, pack(me));
  std::vector<Tile> tiles;
  std::optional<LocalWorker> local;
  if (me.ok) {
    tiles = distributed_tiles(settings, channel.size());
    local.emplace(*renderer, tiles, *runner, me.threads);
  }
  bool stop = false;
  while (!stop) {
    bool any = false;
    while (std::optional<Message> m = channel.receive()) {
      any = true;
      if (m->from != 0) throw std::runtime_error("distributed render: rank " + std::to_string(channel.rank()) +
                                                 " got a message from rank " + std::to_string(m->from));
      if (m->kind == MessageKind::Stop) {
        stop = true;
        break;
      }
      if (m->kind != MessageKind::Unit || !local)
        throw std::runtime_error("distributed render: rank " + std::to_string(channel.rank()) + " got a " +
                                 std::to_string(static_cast<int>(m->kind)));
      local->push(unpack_task(m->bytes));
    }
    if (local)
      while (std::optional<UnitResult> r = local->take_result()) channel.send(0, MessageKind::Result, pack(*r)), any = true;
    if (!any && !stop) {
      if (local) local->wait_for_result(kPoll);
      else std::this_thread::sleep_for(kPoll);
    }
  }
  if (local) {
    local->stop();
    while (std::optional<UnitResult> r = local->take_result()) channel.send(0, MessageKind::Result, pack(*r));
  }
  channel.send(0, MessageKind::Done, {});
  channel.flush();
}

void abandon_distributed(Channel& channel) {
  for (int rank = 1; rank < channel.size(); ++rank) channel.send(rank, MessageKind::Stop, {});
  int done = 0;
  while (done < channel.size() - 1) {
    std::optional<Message> m = channel.receive();
    if (!m) {
      std::this_thread::sleep_for(kPoll);
      continue;
    }
    if (m->kind == MessageKind::Done) ++done;
  }
  channel.flush();
}

}  // namespace lancer
