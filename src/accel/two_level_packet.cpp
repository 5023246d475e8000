// Packet traversal of the two-level accelerator: up to 64 rays whose directions share
// their signs walk the top level together (a shared stack; per ray its fat interval, as
// the single-ray traversal computes it, and an active bit), and at each leaf enter each
// instance as one packet of the active rays, moved into its space and with tfar narrowed
// by the tie rule (two_level.h). A ray leaves a subtree under the same test as a single
// ray, and the answer is the same lexicographic minimum whatever the visit order, so each
// lane's result is intersect's bit for bit. Packets with mixed signs, and rays that the
// single-ray path scans (two_level_ray.h), go one ray at a time. A moving instance is
// entered by each lane at its own time (instance_at per lane, as a single ray would),
// reusing the transform of the previous lane when the times are the same bits.
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

// The packet's top-level rays. `active` holds the lanes that traverse; `coherent` is false
// when two of them point opposite ways on some axis (rays parallel to it agree with both).
struct PacketSetup {
  TopRay rays[kPacket];
  std::uint64_t active = 0;
  std::uint64_t scan = 0;  // lanes for the single-ray path
  bool negative[3] = {false, false, false};
  bool coherent = true;
};

void setup_packet(const Ray* rays, int count, const Bounds3& root, double beta, double extent, PacketSetup& p) {
  bool pos[3] = {false, false, false}, neg[3] = {false, false, false};
  for (int k = 0; k < count; ++k) {
    p.rays[k] = setup_top_ray(rays[k], root, beta, extent);
    const std::uint64_t bit = std::uint64_t(1) << k;
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

// instance_at for the lanes entering one instance, in turn: a lane whose time has the same
// bits as the last one's reuses its transform (instance_at is deterministic, so the result
// is the same bits either way). Static instances are themselves.
class LaneInstance {
 public:
  LaneInstance(const InstancedGeometry& motions, const Instance& inst) : motions_(motions), inst_(inst) {}
  const Instance& at(float time) {
    if (inst_.motion == kNoHit) return inst_;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(time);
    if (!have_ || bits != bits_) {
      moved_ = instance_at(motions_, inst_, time);
      bits_ = bits;
      have_ = true;
    }
    return moved_;
  }

 private:
  const InstancedGeometry& motions_;
  const Instance& inst_;
  Instance moved_;
  std::uint32_t bits_ = 0;
  bool have_ = false;
};

// The shared stack: per entry a node and its lanes, per lane its interval.
struct PacketStack {
  std::uint32_t node[kTopLevelStackSize];
  std::uint64_t mask[kTopLevelStackSize];
  double tmin[kTopLevelStackSize][kPacket];
  double tmax[kTopLevelStackSize][kPacket];
};

// Descends from (node, mask) with the lanes' intervals in tmin/tmax to a leaf, pushing the
// far children some lane still needs; returns false when no lane reaches a leaf.
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

void TwoLevelAccelerator::intersect_packet64(const Ray* rays, Hit* hits, int count) const {
  PacketSetup p;
  setup_packet(rays, count, top_.bounds(), beta_, extent_, p);
  for (int k = 0; k < count; ++k) hits[k] = Hit{};
  const std::uint64_t single = p.coherent ? p.scan : (p.scan | p.active);
  for (std::uint64_t m = single; m != 0; m &= m - 1) hits[std::countr_zero(m)] = intersect(rays[std::countr_zero(m)]);
  if (!p.coherent || p.active == 0) return;

  PacketStack stack;
  two_level::Mailbox mailbox;
  double tmin[kPacket], tmax[kPacket];
  Ray local[kPacket];
  Hit local_hits[kPacket];
  int lane_of[kPacket];
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  int sp = 0;
  stack.node[sp] = 0;
  stack.mask[sp] = p.active;
  for (int k = 0; k < count; ++k) stack.tmin[sp][k] = p.rays[k].tmin, stack.tmax[sp][k] = p.rays[k].tmax;
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
      const Instance& inst = instances_[i];
      LaneInstance lane_inst(motions_, inst);
      int n = 0;
      const bool moves = inst.motion != kNoHit;
      for (std::uint64_t m = mailbox.enter(i, mask); m != 0; m &= m - 1) {
        const int k = std::countr_zero(m);
        if (moves && !fat_ray_meets_box(p.rays[k], moving_boxes_[i])) continue;
        local[n] = ray_to_object(lane_inst.at(rays[k].time), rays[k]);
        if (hits[k].valid()) local[n].tfar = i < hits[k].instance ? std::nextafter(hits[k].t, kInfinity) : hits[k].t;
        lane_of[n++] = k;
      }
      if (n == 0) continue;
      bottoms_[inst.mesh]->intersect_packet(local, local_hits, n);
      for (int q = 0; q < n; ++q) {
        if (!local_hits[q].valid()) continue;
        Hit& h = hits[lane_of[q]];
        h = local_hits[q];
        h.prim += mesh_first_[inst.mesh];
        h.instance = i;
      }
    }
  }
}

void TwoLevelAccelerator::occluded_packet64(const Ray* rays, bool* occluded, int count) const {
  PacketSetup p;
  setup_packet(rays, count, top_.bounds(), beta_, extent_, p);
  for (int k = 0; k < count; ++k) occluded[k] = false;
  const std::uint64_t single = p.coherent ? p.scan : (p.scan | p.active);
  for (std::uint64_t m = single; m != 0; m &= m - 1)
    occluded[std::countr_zero(m)] = this->occluded(rays[std::countr_zero(m)]);
  if (!p.coherent || p.active == 0) return;

  PacketStack stack;
  two_level::Mailbox mailbox;
  double tmin[kPacket], tmax[kPacket];
  Ray local[kPacket];
  bool local_blocked[kPacket];
  int lane_of[kPacket];
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  std::uint64_t open = p.active;  // lanes not yet known to be occluded
  int sp = 0;
  stack.node[sp] = 0;
  stack.mask[sp] = p.active;
  for (int k = 0; k < count; ++k) stack.tmin[sp][k] = p.rays[k].tmin, stack.tmax[sp][k] = p.rays[k].tmax;
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
      const Instance& inst = instances_[i];
      LaneInstance lane_inst(motions_, inst);
      int n = 0;
      const bool moves = inst.motion != kNoHit;
      for (std::uint64_t m = mailbox.enter(i, mask); m != 0; m &= m - 1) {
        const int k = std::countr_zero(m);
        if (moves && !fat_ray_meets_box(p.rays[k], moving_boxes_[i])) continue;
        local[n] = ray_to_object(lane_inst.at(rays[k].time), rays[k]);
        lane_of[n++] = k;
      }
      if (n == 0) continue;
      bottoms_[inst.mesh]->occluded_packet(local, local_blocked, n);
      for (int q = 0; q < n; ++q) {
        if (!local_blocked[q]) continue;
        occluded[lane_of[q]] = true;
        mask &= ~(std::uint64_t(1) << lane_of[q]);
        open &= ~(std::uint64_t(1) << lane_of[q]);
      }
    }
  }
}

}  // namespace lancer
