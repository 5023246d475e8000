#include "accel/kd_build_partition.h"

#include <tbb/parallel_for.h>

#include "accel/kd_build_clip.h"
#include "accel/kd_build_events.h"

namespace lancer::kd {
namespace {

// Side of a ref that does not straddle the plane, or 0 when it straddles it.
std::uint8_t classify(const Bounds3& b, int axis, float pos, PlanarSide planar) {
  const float lo = b.lo[axis], hi = b.hi[axis];
  if (lo == hi) {
    if (lo < pos) return kInLeft;
    if (lo > pos) return kInRight;
    return planar == PlanarSide::Left ? kInLeft : kInRight;
  }
  if (hi <= pos) return kInLeft;
  if (lo >= pos) return kInRight;
  return 0;
}

}  // namespace

bool partition_node(const TriangleSoA& tris, NodeInput& in, const SplitChoice& choice, bool big, bool threads,
                    NodeInput& left, NodeInput& right, BuildScratch& scratch) {
  const std::size_t n = in.refs.size();
  const int axis = choice.axis;
  left.cell = in.cell;
  right.cell = in.cell;
  left.cell.hi[axis] = choice.pos;
  right.cell.lo[axis] = choice.pos;

  std::vector<std::uint8_t>& side = scratch.side;
  std::vector<std::uint32_t>& straddling = scratch.straddling;
  side.resize(n);
  straddling.clear();
  for (std::size_t i = 0; i < n; ++i) {
    side[i] = classify(in.refs[i].box, axis, choice.pos, choice.planar);
    if (side[i] == 0) straddling.push_back(static_cast<std::uint32_t>(i));
  }

  // Perfect splits: clip each straddling triangle to both child cells.
  std::vector<Bounds3>& clip_left = scratch.clip_left;
  std::vector<Bounds3>& clip_right = scratch.clip_right;
  clip_left.resize(straddling.size());
  clip_right.resize(straddling.size());
  auto clip_range = [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const Ref& r = in.refs[straddling[k]];
      clip_left[k] = clipped_triangle_bounds(tris, r.tri, left.cell);
      clip_right[k] = clipped_triangle_bounds(tris, r.tri, right.cell);
      if (clip_left[k].empty() && clip_right[k].empty()) {
        // Cannot happen for a triangle that meets the parent cell; if rounding ever says
        // so, keep it on both sides (conservative) rather than lose it.
        clip_left[k] = r.box;
        clip_left[k].hi[axis] = choice.pos;
        clip_right[k] = r.box;
        clip_right[k].lo[axis] = choice.pos;
      }
    }
  };
  if (threads && straddling.size() > 4096) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, straddling.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) { clip_range(r.begin(), r.end()); });
  } else {
    clip_range(0, straddling.size());
  }
  for (std::size_t k = 0; k < straddling.size(); ++k)
    side[straddling[k]] = kReclipped | (clip_left[k].empty() ? 0 : kInLeft) | (clip_right[k].empty() ? 0 : kInRight);

  std::size_t nl = 0, nr = 0;
  for (std::uint8_t s : side) {
    nl += (s & kInLeft) ? 1 : 0;
    nr += (s & kInRight) ? 1 : 0;
  }
  if (nl + nr > in.budget || nl + nr == 0) return false;

  // Child ref indices (children keep the parent's order, ascending triangle index), and
  // the reclipped refs of each child with their new bounds, for their fresh events.
  const bool both = !big;  // a big node gives events to its left child only
  std::vector<std::uint32_t>& remap_left = scratch.remap_left;
  std::vector<std::uint32_t>& remap_right = scratch.remap_right;
  remap_left.resize(n);
  if (both) remap_right.resize(n);
  scratch.reclipped_left.clear();
  scratch.reclipped_right.clear();
  scratch.reclipped_left_box.clear();
  scratch.reclipped_right_box.clear();
  {
    std::size_t k = 0, il = 0, ir = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t s = side[i];
      const bool reclipped = (s & kReclipped) != 0;
      if (s & kInLeft) {
        remap_left[i] = static_cast<std::uint32_t>(il);
        if (reclipped) {
          scratch.reclipped_left.push_back(static_cast<std::uint32_t>(il));
          scratch.reclipped_left_box.push_back(clip_left[k]);
        }
        ++il;
      }
      if (s & kInRight) {
        if (both) remap_right[i] = static_cast<std::uint32_t>(ir);
        if (reclipped && both) {
          scratch.reclipped_right.push_back(static_cast<std::uint32_t>(ir));
          scratch.reclipped_right_box.push_back(clip_right[k]);
        }
        ++ir;
      }
      if (reclipped) ++k;
    }
  }

  // Events first, refs after: a big node frees its events axis by axis while splicing, so
  // that they are gone before the right child's refs are made (the build's peak memory).
  if (!in.events.empty()) {
    for (int a = 0; a < 3; ++a) {
      left.events.axis[a] = scratch.take_events();
      right.events.axis[a] = scratch.take_events();
    }
    splice_events(in.events, nl, nr, scratch, left.events, right.events,
                  both ? SpliceTo::Both : SpliceTo::LeftOnly);
  }

  // A big node writes its left refs over its own, in place (each parent ref gives at most
  // one left ref, so the write never overtakes the read): parent and children then hold
  // n + nr refs at once instead of n + nl + nr. A small node keeps its vectors for reuse.
  Ref* const parent = in.refs.data();
  if (big) {
    left.refs = std::move(in.refs);
  } else {
    left.refs = scratch.take_refs();
    left.refs.reserve(nl);
  }
  right.refs = scratch.take_refs();
  right.refs.reserve(nr);
  std::size_t k = 0, next_left = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t s = side[i];
    const bool reclipped = (s & kReclipped) != 0;
    const Ref r = parent[i];
    if (s & kInLeft) {
      const Ref out{r.tri, reclipped ? clip_left[k] : r.box};
      if (big) {
        parent[next_left] = out;
      } else {
        left.refs.push_back(out);
      }
      ++next_left;
    }
    if (s & kInRight) right.refs.push_back({r.tri, reclipped ? clip_right[k] : r.box});
    if (reclipped) ++k;
  }
  if (big) left.refs.resize(nl);

  // Budget shares: budget * nl / (nl + nr) >= nl because nl + nr <= budget. The budget is
  // below 2^32 and nl below 2^30 (kd_build.cpp checks), so the product fits in 64 bits.
  const std::size_t total = nl + nr;
  left.budget = in.budget * nl / total;
  right.budget = in.budget * nr / total;
  left.depth = right.depth = in.depth + 1;

  scratch.recycle(in);
  return true;
}

}  // namespace lancer::kd
