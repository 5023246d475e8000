#include "render/tile_scheduler.h"

#include <algorithm>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace lancer {

std::vector<Tile> make_tiles(int width, int height, int tile_size) {
  if (width <= 0 || height <= 0 || tile_size <= 0)
    throw std::invalid_argument("tiles: image size and tile size must be positive");
  std::vector<Tile> tiles;
  for (int y = 0; y < height; y += tile_size)
    for (int x = 0; x < width; x += tile_size)
      tiles.push_back({x, y, std::min(x + tile_size, width), std::min(y + tile_size, height)});
  return tiles;
}

void for_each_tile(const std::vector<Tile>& tiles, int threads, const std::function<void(const Tile&)>& render_tile,
                   const std::function<void(std::size_t, std::size_t)>& on_done) {
  TileRunner runner(threads);
  runner.run(tiles, render_tile, on_done, tiles.size());
}

namespace {
int checked_threads(int threads) {
  if (threads < 0) throw std::invalid_argument("tiles: thread count must be >= 0");
  return threads > 0 ? threads : tbb::task_arena::automatic;
}
}  // namespace

TileRunner::TileRunner(int threads) : arena_(checked_threads(threads)) {}

void TileRunner::run(const std::vector<Tile>& tiles, const std::function<void(const Tile&)>& render_tile,
                     const std::function<void(std::size_t, std::size_t)>& on_done, std::size_t total) {
  arena_.execute([&] {
    // One task per tile: tiles cost very different amounts, so let TBB steal single tiles.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            render_tile(tiles[i]);
            const std::size_t n = done_.fetch_add(1, std::memory_order_relaxed) + 1;
            if (on_done) on_done(n, total);
          }
        },
        tbb::simple_partitioner());
  });
}

void TileRunner::run_ranges(std::size_t n, std::size_t grain,
                            const std::function<void(std::size_t, std::size_t)>& body) {
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(grain, 1)),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  });
}

}  // namespace lancer
