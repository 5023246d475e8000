#include "dist/tile_queue.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace lancer {

namespace {

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("distributed render: " + what); }

}  // namespace

TileQueue::TileQueue(const std::vector<Tile>& tiles, RenderState& state, int spp)
    : tiles_(tiles), state_(state), spp_(spp), pass_(tiles.size()), flying_(tiles.size()) {
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const Tile& tile = tiles[t];
    if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > state.width || tile.y1 > state.height || tile.x0 >= tile.x1 ||
        tile.y0 >= tile.y1)
      refuse("a tile outside the image");
    const std::size_t n = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0);
    std::uint32_t least = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t i = 0; i < n; ++i) least = std::min(least, state.count[pixel(tile, i)]);
    if (least > static_cast<std::uint32_t>(spp)) refuse("a tile already has more than spp samples");
    pass_[t] = static_cast<int>(least);
    passes_.insert(pass_[t]);
    if (pass_[t] < spp) {
      idle_.emplace(pass_[t], static_cast<std::uint32_t>(t));
      ++incomplete_;
    }
    total_ += static_cast<std::uint64_t>(spp - pass_[t]);
  }
}

std::size_t TileQueue::pixel(const Tile& tile, std::size_t i) const {
  const auto w = static_cast<std::size_t>(tile.x1 - tile.x0);
  return (static_cast<std::size_t>(tile.y0) + i / w) * static_cast<std::size_t>(state_.width) +
         static_cast<std::size_t>(tile.x0) + i % w;
}

std::optional<UnitTask> TileQueue::next(int passes) {
  if (idle_.empty()) return std::nullopt;
  const auto [from, t] = *idle_.begin();
  idle_.erase(idle_.begin());
  UnitTask task;
  task.unit.id = next_id_++;
  task.unit.tile = t;
  task.unit.first_pass = from;
  task.unit.passes = std::min(std::max(passes, 1), spp_ - from);
  const Tile& tile = tiles_[t];
  const std::size_t n = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0);
  task.sums.sum.resize(n);
  task.sums.count.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = pixel(tile, i);
    task.sums.sum[i] = state_.sum[p];
    task.sums.count[i] = state_.count[p];
  }
  flying_[t] = task.unit;
  ++in_flight_;
  return task;
}

void TileQueue::finish(const UnitResult& r) {
  const std::uint32_t t = r.unit.tile;
  if (t >= tiles_.size() || !flying_[t] || flying_[t]->id != r.unit.id || flying_[t]->first_pass != r.unit.first_pass ||
      flying_[t]->passes != r.unit.passes)
    refuse("a result for unit " + std::to_string(r.unit.id) + ", which is not in flight on tile " + std::to_string(t));
  const Tile& tile = tiles_[t];
  const std::size_t n = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0);
  if (r.sums.sum.size() != n || r.sums.count.size() != n || r.passes_done < 0 || r.passes_done > r.unit.passes)
    refuse("a result that does not fit tile " + std::to_string(t));
  const int reached = r.unit.first_pass + r.passes_done;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t before = state_.count[pixel(tile, i)], after = r.sums.count[i];
    // Each pixel has had every pass up to `reached` (or was ahead already), never more than spp.
    if (after < before || after < static_cast<std::uint32_t>(reached) || after > static_cast<std::uint32_t>(spp_))
      refuse("a result for tile " + std::to_string(t) + " with a pixel at " + std::to_string(after) +
             " samples (it had " + std::to_string(before) + ", the unit reached pass " + std::to_string(reached) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = pixel(tile, i);
    state_.sum[p] = r.sums.sum[i];
    state_.count[p] = r.sums.count[i];
  }
  flying_[t].reset();
  --in_flight_;
  passes_.erase(passes_.find(pass_[t]));
  done_ += static_cast<std::uint64_t>(reached - pass_[t]);
  pass_[t] = reached;
  passes_.insert(reached);
  if (reached < spp_) idle_.emplace(reached, t);
  else --incomplete_;
}

int TileQueue::least_pass() const { return passes_.empty() ? spp_ : *passes_.begin(); }

void TileQueue::settle_passes() const { state_.passes = least_pass(); }

}  // namespace lancer
