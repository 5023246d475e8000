// Rank 0's book of a distributed render: which passes of which tile to hand out next, and
// the render's state, which results update. A tile is in at most one unit at a time (its
// sums travel with it); the idle tile least far along goes first, so the image fills evenly
// and a stop leaves every tile within about a unit of the others. Tiles in flight keep
// their last state here, so the state is always one a resume can continue.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "dist/work_unit.h"
#include "render/render_state.h"
#include "render/tile_scheduler.h"

namespace lancer {

class TileQueue {
 public:
  // Keeps references to both. Each tile starts at the fewest samples its pixels have in
  // `state` (tiles' image's, every count at most spp, as check_render_state checks).
  TileQueue(const std::vector<Tile>& tiles, RenderState& state, int spp);

  // The idle tile whose pixels are least far along (the lowest index among equals), for up
  // to `passes` (at least 1) passes, with its sums. nullopt when every tile not at spp is
  // in flight.
  std::optional<UnitTask> next(int passes);

  // Writes a unit's sums back and makes its tile idle. Throws std::invalid_argument for a
  // result that is not the unit in flight on its tile or does not fit it (a count below
  // what the tile had or above spp).
  void finish(const UnitResult& result);

  bool complete() const { return incomplete_ == 0; }
  std::size_t in_flight() const { return in_flight_; }
  // The fewest passes any tile has had: what every pixel has.
  int least_pass() const;
  // Tile-passes done since the start, and all there are to do to reach spp: the progress.
  std::uint64_t tile_passes_done() const { return done_; }
  std::uint64_t total_tile_passes() const { return total_; }
  // Sets state.passes to least_pass().
  void settle_passes() const;

 private:
  std::size_t pixel(const Tile& tile, std::size_t i) const;

  const std::vector<Tile>& tiles_;
  RenderState& state_;
  int spp_;
  std::vector<int> pass_;                         // per tile: the fewest samples of its pixels
  std::vector<std::optional<WorkUnit>> flying_;   // per tile: its unit in flight
  std::set<std::pair<int, std::uint32_t>> idle_;  // (pass_, tile) of the idle tiles not at spp
  std::multiset<int> passes_;                     // every tile's pass_, for least_pass
  std::size_t in_flight_ = 0, incomplete_ = 0;
  std::uint32_t next_id_ = 0;
  std::uint64_t done_ = 0, total_ = 0;
};

}  // namespace lancer
