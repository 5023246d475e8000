// Splits an image into square tiles and renders them in parallel with oneTBB.
// Tiles carry no state between them, so the result cannot depend on their order.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

#include <tbb/task_arena.h>

namespace lancer {

// Pixels [x0, x1) x [y0, y1).
struct Tile {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Row-major tiles of tile_size x tile_size covering a width x height image (the last
// row and column may be smaller). All three numbers must be positive.
std::vector<Tile> make_tiles(int width, int height, int tile_size);

// Calls render_tile(tile) once for each tile, in parallel on at most `threads` threads
// (0: as many as the hardware has) inside a tbb::task_arena, then on_done(tiles finished
// so far, tiles in total) from the same worker thread. Both callbacks must be thread-safe.
void for_each_tile(const std::vector<Tile>& tiles, int threads, const std::function<void(const Tile&)>& render_tile,
                   const std::function<void(std::size_t, std::size_t)>& on_done);

// for_each_tile with one task arena kept across calls (a progressive render runs one pass
// over the tiles per sample). on_done's counts run on from call to call; `total` is what
// it reports as the whole.
class TileRunner {
 public:
  explicit TileRunner(int threads);
  // The threads it runs on (what `threads` asked for, or the hardware's).
  int concurrency() { return arena_.max_concurrency(); }
  void run(const std::vector<Tile>& tiles, const std::function<void(const Tile&)>& render_tile,
           const std::function<void(std::size_t, std::size_t)>& on_done, std::size_t total);
  // Other work in the same arena: body(begin, end) over [0, n) in ranges of about `grain`
  // (at least 1), in parallel. The body must not depend on how the range is split.
  void run_ranges(std::size_t n, std::size_t grain, const std::function<void(std::size_t, std::size_t)>& body);

 private:
  tbb::task_arena arena_;
  std::atomic<std::size_t> done_{0};
};

}  // namespace lancer
