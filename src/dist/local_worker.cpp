#include "dist/local_worker.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace lancer {

UnitResult render_unit(const SampleRenderer& renderer, const Tile& tile, UnitTask task, TileRunner& runner,
                       const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const WorkUnit& unit = task.unit;
  const int w = tile.x1 - tile.x0;
  const auto pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(tile.y1 - tile.y0);
  if (task.sums.sum.size() != pixels || task.sums.count.size() != pixels || unit.passes < 1 || unit.first_pass < 0)
    throw std::invalid_argument("distributed render: unit " + std::to_string(unit.id) + " does not fit its tile");
  // Every pass's samples first, in parallel (they do not depend on each other); with fewer
  // passes than threads, each pass in strips of block rows too (a sample depends on its
  // pixel, not on what else its wavefront holds), ...
  const int strips = (tile.y1 - tile.y0 + kBlockSide - 1) / kBlockSide;
  const int threads = runner.concurrency();
  const int parts = unit.passes >= threads ? 1 : std::min(strips, (threads + unit.passes - 1) / unit.passes);
  auto part = [&](int j) {  // rows of blocks [j * strips / parts, (j + 1) * strips / parts)
    Tile t = tile;
    t.y0 = tile.y0 + kBlockSide * (j * strips / parts);
    t.y1 = std::min(tile.y1, tile.y0 + kBlockSide * ((j + 1) * strips / parts));
    return t;
  };
  std::vector<glm::vec3> radiance(static_cast<std::size_t>(unit.passes) * pixels);
  std::vector<char> finished(static_cast<std::size_t>(unit.passes) * static_cast<std::size_t>(parts), 0);
  std::atomic<std::uint64_t> rays{0}, primary_rays{0};
  std::atomic<Clock::rep> primary_ticks{0};
  auto must_stop = [&] { return stop.load(std::memory_order_relaxed); };
  runner.run_ranges(finished.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t job = begin; job < end; ++job) {
      const std::size_t k = job / static_cast<std::size_t>(parts);
      glm::vec3* out = radiance.data() + k * pixels;
      auto take = [&](const PixelBlock& block, const glm::vec3* L) {
        for (int i = 0; i < block.pixel_count(); ++i)
          out[static_cast<std::size_t>((block.y0 + i / block.width() - tile.y0) * w + block.x0 + i % block.width() -
                                       tile.x0)] = L[i];
      };
      SampleRenderer::Counters counters;
      const bool done = renderer.render_tile(
          part(static_cast<int>(job % static_cast<std::size_t>(parts))), unit.first_pass + static_cast<int>(k),
          [](const PixelBlock&) { return true; }, take, must_stop, counters);
      finished[job] = done ? 1 : 0;
      rays += counters.rays;
      primary_rays += counters.primary_rays;
      primary_ticks += counters.primary_time.count();
    }
  });
  // ... then added in pass order, as one process adds them.
  UnitResult r;
  r.unit = unit;
  r.passes_done = static_cast<std::int32_t>(
      (std::find(finished.begin(), finished.end(), 0) - finished.begin()) / parts);
  for (int k = 0; k < r.passes_done; ++k) {
    const auto s = static_cast<std::uint32_t>(unit.first_pass + k);
    const glm::vec3* L = radiance.data() + static_cast<std::size_t>(k) * pixels;
    for (std::size_t i = 0; i < pixels; ++i) {
      if (task.sums.count[i] != s) continue;  // a pixel a stop mid-pass left ahead
      task.sums.sum[i] += glm::dvec3(L[i]);
      ++task.sums.count[i];
    }
  }
  r.sums = std::move(task.sums);
  r.rays = rays.load();
  r.primary_rays = primary_rays.load();
  r.primary_seconds = std::chrono::duration<double>(Clock::duration(primary_ticks.load())).count();
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

LocalWorker::LocalWorker(const SampleRenderer& renderer, const std::vector<Tile>& tiles, TileRunner& runner,
                         int threads)
    : renderer_(renderer), tiles_(tiles), runner_(runner), threads_(std::max(threads, 1)),
      thread_([this] { run(); }) {}

LocalWorker::~LocalWorker() { stop(); }

void LocalWorker::push(UnitTask task) {
  if (task.unit.tile >= tiles_.size())
    throw std::invalid_argument("distributed render: a unit for tile " + std::to_string(task.unit.tile) + " of " +
                                std::to_string(tiles_.size()));
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    units_.push_back(std::move(task));
  }
  wake_worker_.notify_one();
}

std::optional<UnitResult> LocalWorker::take_result() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (failure_) std::rethrow_exception(failure_);
  if (results_.empty()) return std::nullopt;
  UnitResult r = std::move(results_.front());
  results_.pop_front();
  return r;
}

void LocalWorker::wait_for_result(std::chrono::microseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_owner_.wait_for(lock, timeout, [this] { return !results_.empty() || failure_; });
}

void LocalWorker::stop() {
  stop_.store(true);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
    units_.clear();
  }
  wake_worker_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void LocalWorker::run() {
  for (;;) {
    UnitTask task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_worker_.wait(lock, [this] { return quit_ || !units_.empty(); });
      if (quit_) return;
      task = std::move(units_.front());
      units_.pop_front();
    }
    try {
      const Tile& tile = tiles_[task.unit.tile];
      UnitResult r = render_unit(renderer_, tile, std::move(task), runner_, stop_);
      r.threads = threads_;
      const std::lock_guard<std::mutex> lock(mutex_);
      results_.push_back(std::move(r));
    } catch (...) {  // out of memory, most likely: the owner rethrows it
      const std::lock_guard<std::mutex> lock(mutex_);
      failure_ = std::current_exception();
      quit_ = true;
    }
    wake_owner_.notify_one();
  }
}

}  // namespace lancer
