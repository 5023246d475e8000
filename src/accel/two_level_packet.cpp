// Packet traversal of the two-level accelerator: up to 64 rays whose directions share
// their signs walk the top level together (a shared stack; per ray its fat interval, as
// the single-ray traversal computes it, and an active bit), and at each leaf enter each
// instance as one packet of the active rays, moved into its space and with tfar narrowed
// by the tie rule (two_level.h). A ray leaves a subtree under the same test as a single
// ray, and the answer is the same lexicographic minimum whatever the visit order, so each
// lane's result is intersect's bit for bit. Packets with mixed signs, and rays that the
// single-ray path scans (two_level_ray.h), go one ray at a time. A moving instance is
// entered by each lane at its own time (at_time per lane, as a single ray would). Direct
// instances (two_level.h) take the whole packet first.
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "accel/two_level.h"
#include "accel/two_level_ray.h"

namespace lancer {

namespace {

using two_level::lowest_hit_in_cell;
using two_level::fat_ray_meets_box;
using two_level::setup_top_ray;
using two_level::top_step;
using two_level::TopPlan;
using two_level::TopRay;
using two_level::TopStep;

constexpr int kPacket = 64;

}  // namespace

// The packet's top-level rays. `active` holds the lanes that traverse the top level's tree
// (none with few instances, where `few` holds each instance's lanes); `coherent` is false
// when two of them point opposite ways on some axis (rays parallel to it agree with both).
namespace two_level {
struct PacketSetup {
  TopRay rays[kPacket];
  std::uint64_t active = 0;
  std::uint64_t scan = 0;  // lanes for the single-ray path
  // Few instances: per few_top_ entry, the lanes that may meet it (the others skip it).
  std::uint64_t few[TwoLevelAccelerator::kFewTopInstances] = {};
  bool negative[3] = {false, false, false};
  bool coherent = true;
};
}  // namespace two_level

// Lanes in `skip` stay out (Miss); a lane with a hit in `hits` (when given) is clipped to
// it, as intersect_top clips a single ray. Most lanes with a finite range are settled by
// their segment box (two_level_ray.h) without the division of setup_top_ray: against the
// top level's box, or with few instances against each one's (few_met).
void TwoLevelAccelerator::setup_packet(const Ray* rays, const Hit* hits, std::uint64_t skip, int count,
                                       two_level::PacketSetup& p) const {
  const bool few = !few_top_.empty();
  bool pos[3] = {false, false, false}, neg[3] = {false, false, false};
  for (int k = 0; k < count; ++k) {
    const std::uint64_t bit = std::uint64_t(1) << k;
    p.rays[k].plan = TopPlan::Miss;
    if (skip & bit) continue;
    Ray clipped = rays[k];
    if (hits && hits[k].valid()) clipped.tfar = two_level::smaller(hits[k].t, clipped.tfar);  // keeps a NaN (Scan)
    if (few) {
      // Few lanes need no common direction, and a lane the top level would scan enters
      // every instance here too.
      for (unsigned met = few_met(clipped, p.rays[k]); met != 0; met &= met - 1) p.few[std::countr_zero(met)] |= bit;
      continue;
    }
    if (two_level::segment_misses(clipped, top_.bounds(), beta_, extent_)) continue;
    setup_top_ray(clipped, top_.bounds(), beta_, extent_, p.rays[k]);
    if (p.rays[k].plan == TopPlan::Scan) p.scan |= bit;
    if (p.rays[k].plan != TopPlan::Traverse) continue;
    p.active |= bit;
    for (int a = 0; a < 3; ++a) {
      if (p.rays[k].parallel[a]) continue;
      (p.rays[k].negative[a] ? neg[a] : pos[a]) = true;
    }
  }
  for (int a = 0; a < 3; ++a) {
    p.negative[a] = neg[a];
    if (pos[a] && neg[a]) p.coherent = false;
  }
}

namespace {

// The shared stack: per entry a node and its lanes, per lane its interval.
struct PacketStack {
  std::uint32_t node[kTopLevelStackSize];
  std::uint64_t mask[kTopLevelStackSize];
  double tmin[kTopLevelStackSize][kPacket];
  double tmax[kTopLevelStackSize][kPacket];
};

// Descends from (node, mask) with the lanes' intervals in tmin/tmax to a leaf, pushing the
// far children some lane still needs; returns false when no lane reaches a leaf.
using two_level::PacketSetup;

bool descend(const PacketSetup& p, const KdNode* nodes, std::uint32_t& node, std::uint64_t& mask, double* tmin,
             double* tmax, PacketStack& stack, int& sp) {
  while (!nodes[node].is_leaf()) {
    const KdNode n = nodes[node];
    const int axis = n.axis();
    const bool neg = p.negative[axis];
    std::uint64_t near_mask = 0, far_mask = 0;
    for (std::uint64_t m = mask; m != 0; m &= m - 1) {
      const int k = std::countr_zero(m);
      const TopStep step = top_step(p.rays[k], axis, n.split(), neg, tmin[k], tmax[k]);
      const std::uint64_t bit = std::uint64_t(1) << k;
      if (step.far) {
        far_mask |= bit;
        stack.tmin[sp][k] = step.far_min;
        stack.tmax[sp][k] = tmax[k];
      }
      if (step.near) {
        near_mask |= bit;
        tmax[k] = step.near_max;
      }
    }
    const std::uint32_t near = neg ? n.right_child() : n.left_child();
    const std::uint32_t far = neg ? n.left_child() : n.right_child();
    if (far_mask != 0) {
      stack.node[sp] = far;
      stack.mask[sp] = far_mask;
      ++sp;
    }
    if (near_mask == 0) return false;
    node = near;
    mask = near_mask;
  }
  return true;
}

}  // namespace

void TwoLevelAccelerator::intersect_packet(const Ray* rays, Hit* hits, int count) const {
  if (count < 0) throw std::invalid_argument("two-level: negative packet size " + std::to_string(count));
  for (int i = 0; i < count; i += kPacket)
    intersect_packet64(rays + i, hits + i, count - i < kPacket ? count - i : kPacket);
}

void TwoLevelAccelerator::occluded_packet(const Ray* rays, bool* occluded, int count) const {
  if (count < 0) throw std::invalid_argument("two-level: negative packet size " + std::to_string(count));
  for (int i = 0; i < count; i += kPacket)
    occluded_packet64(rays + i, occluded + i, count - i < kPacket ? count - i : kPacket);
}

// The direct instances take the whole packet, in ascending order (two_level.h).
void TwoLevelAccelerator::intersect_direct(const Ray* rays, Hit* hits, int count) const {
  Ray local[kPacket];
  Hit local_hits[kPacket];
  for (std::uint32_t i : direct_list_) {
    const std::uint32_t mesh = instances_[i].mesh;
    if (i == direct_list_.front()) {  // no hit yet: nothing to narrow
      for (int k = 0; k < count; ++k) local[k] = ray_to_object(instances_[i], rays[k]);
    } else {
      for (int k = 0; k < count; ++k) local[k] = entered(i, rays[k], hits[k]);
    }
    bottoms_[mesh]->intersect_packet(local, local_hits, count);
    for (int k = 0; k < count; ++k) {
      if (!local_hits[k].valid()) continue;
      hits[k] = local_hits[k];
      hits[k].prim += mesh_first_[mesh];
      hits[k].instance = i;
    }
  }
}

void TwoLevelAccelerator::intersect_packet64(const Ray* rays, Hit* hits, int count) const {
  for (int k = 0; k < count; ++k) hits[k] = Hit{};
  intersect_direct(rays, hits, count);
  if (top_.bounds().empty()) return;
  two_level::PacketSetup p;
  setup_packet(rays, hits, 0, count, p);
  // Few instances: each is offered to the lanes in turn, whatever their directions.
  const bool few = !few_top_.empty();
  const std::uint64_t single = p.coherent || few ? p.scan : (p.scan | p.active);
  for (std::uint64_t m = single; m != 0; m &= m - 1) intersect_top(rays[std::countr_zero(m)], hits[std::countr_zero(m)]);
  if (few) {
    for (std::size_t j = 0; j < few_top_.size(); ++j) enter_packet(few_top_[j], p.few[j], rays, hits);
    return;
  }
  if (!p.coherent || p.active == 0) return;

  PacketStack stack;
  two_level::Mailbox mailbox;
  double tmin[kPacket], tmax[kPacket];
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  int sp = 0;
  stack.node[sp] = 0;
  stack.mask[sp] = p.active;
  for (std::uint64_t m = p.active; m != 0; m &= m - 1) {
    const int k = std::countr_zero(m);
    stack.tmin[sp][k] = p.rays[k].tmin;
    stack.tmax[sp][k] = p.rays[k].tmax;
  }
  ++sp;
  while (sp > 0) {
    --sp;
    std::uint32_t node = stack.node[sp];
    std::uint64_t mask = 0;
    // Lanes whose best hit lies before this cell can gain nothing in it.
    for (std::uint64_t m = stack.mask[sp]; m != 0; m &= m - 1) {
      const int k = std::countr_zero(m);
      if (hits[k].valid() && double(hits[k].t) < lowest_hit_in_cell(p.rays[k], stack.tmin[sp][k])) continue;
      mask |= std::uint64_t(1) << k;
      tmin[k] = stack.tmin[sp][k];
      tmax[k] = stack.tmax[sp][k];
    }
    if (mask == 0 || !descend(p, nodes, node, mask, tmin, tmax, stack, sp)) continue;

    const KdNode leaf = nodes[node];
    for (std::uint32_t j = 0; j < leaf.count(); ++j) {
      const std::uint32_t i = items[leaf.first_slot() + j];
      enter_packet(i, moving_lanes(i, mailbox.enter(i, mask), rays, p), rays, hits);
    }
  }
}

// The lanes of `lanes` that may meet instance i: for a moving one, those whose fat ray
// meets its box over the piece of the shutter holding their time (meets_moving); all of
// them for another.
std::uint64_t TwoLevelAccelerator::moving_lanes(std::uint32_t i, std::uint64_t lanes, const Ray* rays,
                                                const two_level::PacketSetup& p) const {
  if (instances_[i].motion == kNoHit) return lanes;
  std::uint64_t out = 0;
  for (std::uint64_t m = lanes; m != 0; m &= m - 1) {
    const int k = std::countr_zero(m);
    if (meets_moving(i, p.rays[k], rays[k].time)) out |= std::uint64_t(1) << k;
  }
  return out;
}

// The lanes of `lanes`, moved into instance i's space (each at its own time) as
// local[0..n), tfar narrowed by the tie rule against `hits` when given; lane_of maps them
// back. Returns n.
int TwoLevelAccelerator::gather_lanes(std::uint32_t i, std::uint64_t lanes, const Ray* rays, const Hit* hits,
                                      Ray* local, int* lane_of) const {
  const Hit none;
  int n = 0;
  for (std::uint64_t m = lanes; m != 0; m &= m - 1) {
    const int k = std::countr_zero(m);
    local[n] = entered(i, rays[k], hits ? hits[k] : none);
    lane_of[n++] = k;
  }
  return n;
}

// The lanes of `lanes` enter instance i as one packet (gather_lanes).
void TwoLevelAccelerator::enter_packet(std::uint32_t i, std::uint64_t lanes, const Ray* rays, Hit* hits) const {
  if (lanes == 0) return;
  const Instance& inst = instances_[i];
  Ray local[kPacket];
  Hit local_hits[kPacket];
  int lane_of[kPacket];
  const int n = gather_lanes(i, lanes, rays, hits, local, lane_of);
  bottoms_[inst.mesh]->intersect_packet(local, local_hits, n);
  for (int q = 0; q < n; ++q) {
    if (!local_hits[q].valid()) continue;
    Hit& h = hits[lane_of[q]];
    h = local_hits[q];
    h.prim += mesh_first_[inst.mesh];
    h.instance = i;
  }
}

// The lanes of `lanes` that instance i blocks (tested as enter_packet enters them).
std::uint64_t TwoLevelAccelerator::block_packet(std::uint32_t i, std::uint64_t lanes, const Ray* rays) const {
  std::uint64_t blocked = 0;
  if (lanes == 0) return blocked;
  const Instance& inst = instances_[i];
  Ray local[kPacket];
  bool local_blocked[kPacket];
  int lane_of[kPacket];
  const int n = gather_lanes(i, lanes, rays, nullptr, local, lane_of);
  bottoms_[inst.mesh]->occluded_packet(local, local_blocked, n);
  for (int q = 0; q < n; ++q)
    if (local_blocked[q]) blocked |= std::uint64_t(1) << lane_of[q];
  return blocked;
}

void TwoLevelAccelerator::occluded_packet64(const Ray* rays, bool* occluded, int count) const {
  for (int k = 0; k < count; ++k) occluded[k] = false;
  // The direct instances take the whole packet; the lanes they block are done.
  std::uint64_t done = 0;
  bool direct_blocked[kPacket];
  Ray local[kPacket];
  for (std::uint32_t i : direct_list_) {
    for (int k = 0; k < count; ++k) local[k] = ray_to_object(instances_[i], rays[k]);
    bottoms_[instances_[i].mesh]->occluded_packet(local, direct_blocked, count);
    for (int k = 0; k < count; ++k)
      if (direct_blocked[k]) occluded[k] = true, done |= std::uint64_t(1) << k;
  }
  if (top_.bounds().empty()) return;
  two_level::PacketSetup p;
  setup_packet(rays, nullptr, done, count, p);
  const bool few = !few_top_.empty();
  const std::uint64_t single = p.coherent || few ? p.scan : (p.scan | p.active);
  for (std::uint64_t m = single; m != 0; m &= m - 1)
    occluded[std::countr_zero(m)] = occluded_top(rays[std::countr_zero(m)]);
  if (few) {
    std::uint64_t open = ~std::uint64_t(0);
    for (std::size_t j = 0; j < few_top_.size(); ++j) {
      const std::uint64_t blocked = block_packet(few_top_[j], p.few[j] & open, rays);
      for (std::uint64_t m = blocked; m != 0; m &= m - 1) occluded[std::countr_zero(m)] = true;
      open &= ~blocked;
    }
    return;
  }
  if (!p.coherent || p.active == 0) return;

  PacketStack stack;
  two_level::Mailbox mailbox;
  double tmin[kPacket], tmax[kPacket];
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  std::uint64_t open = p.active;  // lanes not yet known to be occluded
  int sp = 0;
  stack.node[sp] = 0;
  stack.mask[sp] = p.active;
  for (std::uint64_t m = p.active; m != 0; m &= m - 1) {
    const int k = std::countr_zero(m);
    stack.tmin[sp][k] = p.rays[k].tmin;
    stack.tmax[sp][k] = p.rays[k].tmax;
  }
  ++sp;
  while (sp > 0 && open != 0) {
    --sp;
    std::uint32_t node = stack.node[sp];
    std::uint64_t mask = stack.mask[sp] & open;
    for (std::uint64_t m = mask; m != 0; m &= m - 1) {
      const int k = std::countr_zero(m);
      tmin[k] = stack.tmin[sp][k];
      tmax[k] = stack.tmax[sp][k];
    }
    if (mask == 0 || !descend(p, nodes, node, mask, tmin, tmax, stack, sp)) continue;

    const KdNode leaf = nodes[node];
    for (std::uint32_t j = 0; j < leaf.count() && mask != 0; ++j) {
      const std::uint32_t i = items[leaf.first_slot() + j];
      const std::uint64_t blocked = block_packet(i, moving_lanes(i, mailbox.enter(i, mask), rays, p), rays);
      for (std::uint64_t m = blocked; m != 0; m &= m - 1) occluded[std::countr_zero(m)] = true;
      mask &= ~blocked;
      open &= ~blocked;
    }
  }
}

}  // namespace lancer
