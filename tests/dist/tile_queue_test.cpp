// Rank 0's book of a distributed render: which tile goes next, and how results update the
// render's state (dist/tile_queue.h).
#include "dist/tile_queue.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace lancer {
namespace {

// A result that gives every pixel of the unit's tile the unit's passes (sum += pass index).
UnitResult finished(const UnitTask& task, int passes_done = -1) {
  UnitResult r;
  r.unit = task.unit;
  r.passes_done = passes_done < 0 ? task.unit.passes : passes_done;
  r.sums = task.sums;
  for (int k = 0; k < r.passes_done; ++k)
    for (std::size_t i = 0; i < r.sums.count.size(); ++i)
      if (r.sums.count[i] == static_cast<std::uint32_t>(task.unit.first_pass + k)) {
        r.sums.sum[i] += glm::dvec3(task.unit.first_pass + k);
        ++r.sums.count[i];
      }
  return r;
}

TEST(TileQueue, HandsOutTheLeastAdvancedIdleTileFirst) {
  const std::vector<Tile> tiles = make_tiles(8, 4, 4);  // two tiles
  RenderState state;
  state.reset(8, 4);
  TileQueue queue(tiles, state, 10);
  EXPECT_EQ(queue.total_tile_passes(), 20u);
  const auto a = queue.next(3);
  const auto b = queue.next(3);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->unit.tile, 0u);
  EXPECT_EQ(b->unit.tile, 1u);
  EXPECT_EQ(a->unit.first_pass, 0);
  EXPECT_EQ(a->unit.passes, 3);
  EXPECT_NE(a->unit.id, b->unit.id);
  EXPECT_EQ(a->sums.sum.size(), 16u);
  EXPECT_FALSE(queue.next(3)) << "a tile in flight is not handed out twice";
  EXPECT_EQ(queue.in_flight(), 2u);
  // Tile 1 returns first and goes again before tile 0 is back.
  queue.finish(finished(*b));
  const auto c = queue.next(100);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->unit.tile, 1u);
  EXPECT_EQ(c->unit.first_pass, 3);
  EXPECT_EQ(c->unit.passes, 7) << "clipped at spp";
  queue.finish(finished(*a));
  queue.finish(finished(*c));
  EXPECT_EQ(queue.least_pass(), 3);
  const auto d = queue.next(0);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->unit.tile, 0u);
  EXPECT_EQ(d->unit.passes, 1) << "fewer than one pass is one";
  EXPECT_FALSE(queue.complete());
  queue.finish(finished(*d));
  while (const auto u = queue.next(4)) queue.finish(finished(*u));
  EXPECT_TRUE(queue.complete());
  EXPECT_EQ(queue.tile_passes_done(), 20u);
  queue.settle_passes();
  EXPECT_EQ(state.passes, 10);
  for (std::uint32_t n : state.count) EXPECT_EQ(n, 10u);
  for (const glm::dvec3& s : state.sum) EXPECT_EQ(s.x, 45.0);  // 0 + 1 + ... + 9
}

TEST(TileQueue, StartsEachTileWhereAResumedStateLeftIt) {
  const std::vector<Tile> tiles = make_tiles(8, 4, 4);
  RenderState state;
  state.reset(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) state.count[static_cast<std::size_t>(y * 8 + x)] = x < 4 ? 5 : 2;
  state.count[4] = 3;  // one pixel of tile 1 a sample ahead (a stop mid-pass)
  TileQueue queue(tiles, state, 6);
  EXPECT_EQ(queue.total_tile_passes(), 1u + 4u);
  EXPECT_EQ(queue.least_pass(), 2);
  const auto first = queue.next(10);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->unit.tile, 1u);
  EXPECT_EQ(first->unit.first_pass, 2);
  EXPECT_EQ(first->unit.passes, 4);
  EXPECT_EQ(first->sums.count[0], 3u) << "the tile's own pixels, row-major in the tile";
  const UnitResult r = finished(*first);
  EXPECT_EQ(r.sums.count[0], 6u);
  queue.finish(r);
  EXPECT_EQ(state.count[4], 6u);
  EXPECT_EQ(state.sum[4].x, 3.0 + 4.0 + 5.0) << "the pixel ahead took passes 3, 4 and 5 only";
  EXPECT_EQ(state.sum[5].x, 2.0 + 3.0 + 4.0 + 5.0);
}

TEST(TileQueue, AStoppedUnitLeavesItsTileWhereItGotTo) {
  const std::vector<Tile> tiles = make_tiles(4, 4, 4);
  RenderState state;
  state.reset(4, 4);
  TileQueue queue(tiles, state, 8);
  const auto u = queue.next(6);
  ASSERT_TRUE(u);
  queue.finish(finished(*u, 2));
  EXPECT_EQ(queue.least_pass(), 2);
  EXPECT_EQ(queue.tile_passes_done(), 2u);
  const auto v = queue.next(1);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->unit.first_pass, 2);
  EXPECT_EQ(v->sums.count[0], 2u);
}

TEST(TileQueue, RefusesResultsThatAreNotTheUnitInFlightOrDoNotFit) {
  const std::vector<Tile> tiles = make_tiles(8, 4, 4);
  RenderState state;
  state.reset(8, 4);
  TileQueue queue(tiles, state, 8);
  const auto u = queue.next(2);
  ASSERT_TRUE(u);
  UnitResult other = finished(*u);
  other.unit.id += 7;
  EXPECT_THROW(queue.finish(other), std::invalid_argument);
  UnitResult wrong_tile = finished(*u);
  wrong_tile.unit.tile = 1;  // idle
  EXPECT_THROW(queue.finish(wrong_tile), std::invalid_argument);
  UnitResult short_sums = finished(*u);
  short_sums.sums.sum.pop_back();
  short_sums.sums.count.pop_back();
  EXPECT_THROW(queue.finish(short_sums), std::invalid_argument);
  UnitResult lost_samples = finished(*u);
  lost_samples.sums.count[3] = 1;  // the unit said two passes
  EXPECT_THROW(queue.finish(lost_samples), std::invalid_argument);
  UnitResult too_many = finished(*u);
  too_many.sums.count[3] = 9;  // above spp
  EXPECT_THROW(queue.finish(too_many), std::invalid_argument);
  for (std::uint32_t n : state.count) EXPECT_EQ(n, 0u) << "a refused result changes nothing";
  queue.finish(finished(*u));
  EXPECT_THROW(queue.finish(finished(*u)), std::invalid_argument) << "the same result twice";
}

TEST(TileQueue, RefusesTilesOutsideTheImageAndStatesPastSpp) {
  RenderState state;
  state.reset(4, 4);
  EXPECT_THROW(TileQueue(make_tiles(8, 4, 4), state, 4), std::invalid_argument);
  state.count.assign(16, 5);
  EXPECT_THROW(TileQueue(make_tiles(4, 4, 4), state, 4), std::invalid_argument);
  state.count.assign(16, 4);
  const std::vector<Tile> tiles = make_tiles(4, 4, 4);
  TileQueue done(tiles, state, 4);
  EXPECT_TRUE(done.complete());
  EXPECT_FALSE(done.next(1));
}

}  // namespace
}  // namespace lancer
