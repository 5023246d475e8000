#include "accel/two_level.h"

#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "accel/two_level_motion.h"
#include "accel/two_level_norms.h"
#include "accel/two_level_ray.h"
#include "simd/release_free_memory.h"

namespace lancer {

namespace {

using two_level::lowest_hit_in_cell;
using two_level::fat_ray_meets_box;
using two_level::setup_top_ray;
using two_level::top_step;
using two_level::TopPlan;
using two_level::TopRay;
using two_level::TopStep;

using two_level::finite;
using two_level::kMaxNorm;
using two_level::norm_inf;

void validate(const TriangleSoA& tris, const InstancedGeometry& geometry) {
  for (std::size_t m = 0; m < geometry.meshes.size(); ++m) {
    const MeshRange& r = geometry.meshes[m];
    if (std::uint64_t(r.first) + r.count > tris.size())
      throw std::invalid_argument("two-level: mesh " + std::to_string(m) + " (triangles " + std::to_string(r.first) +
                                  " + " + std::to_string(r.count) + ") lies outside the " +
                                  std::to_string(tris.size()) + " triangles");
  }
  if (geometry.instances.size() >= kNoHit) throw std::invalid_argument("two-level: too many instances");
  for (std::size_t i = 0; i < geometry.instances.size(); ++i) {
    const Instance& inst = geometry.instances[i];
    const std::string which = "two-level: instance " + std::to_string(i);
    if (inst.mesh >= geometry.meshes.size())
      throw std::invalid_argument(which + " draws mesh " + std::to_string(inst.mesh) + " of " +
                                  std::to_string(geometry.meshes.size()));
    if (!finite(inst.to_world) || !finite(inst.to_object))
      throw std::invalid_argument(which + " has a transform that is not finite");
    const double l = norm_inf(inst.to_world.linear), r = norm_inf(inst.to_object.linear);
    const double det = glm::determinant(glm::dmat3(inst.to_world.linear));
    if (!(l > 0.0) || !(r > 0.0) || l > kMaxNorm || r > kMaxNorm || det == 0.0)
      throw std::invalid_argument(which + " has a singular transform or one scaling by more than 2^40");
  }
}

// A static instance whose transforms are exactly the identity (the world geometry beside
// instanced or moving meshes).
bool is_identity(const Instance& inst) {
  const Affine identity;
  return inst.motion == kNoHit && inst.to_world.linear == identity.linear && inst.to_world.offset == identity.offset &&
         inst.to_object.linear == identity.linear && inst.to_object.offset == identity.offset;
}

// The mesh's triangles, as their own TriangleSoA (local index = index - first).
TriangleSoA copy_mesh(const TriangleSoA& tris, const MeshRange& r) {
  TriangleSoA out;
  out.reserve(r.count);
  for (std::uint32_t i = 0; i < r.count; ++i)
    out.push_back(tris.vertex(r.first + i, 0), tris.vertex(r.first + i, 1), tris.vertex(r.first + i, 2));
  return out;
}

// The box of the finite triangles (no kernel reports a hit on the others).
Bounds3 finite_bounds(const TriangleSoA& t) {
  Bounds3 b;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const Bounds3 tb = t.triangle_bounds(i);
    if (std::isfinite(tb.lo.x) && std::isfinite(tb.lo.y) && std::isfinite(tb.lo.z) && std::isfinite(tb.hi.x) &&
        std::isfinite(tb.hi.y) && std::isfinite(tb.hi.z))
      b.extend(tb);
  }
  return b;
}

// The object box's 8 corners through to_world in double, widened by alpha (two_level_ray.h)
// plus 2^-20 of the largest coordinate, which covers rounding the double box out to float.
// Without alpha the float rounding of ray_to_object could put a true hit a few ulps
// outside the box, and the top level would never visit the instance. Returns alpha's
// partner beta through `beta`.
Bounds3 world_box(const Instance& inst, const Bounds3& object, double& beta) {
  const double l = norm_inf(inst.to_world.linear), r = norm_inf(inst.to_object.linear);
  beta = 0x1p-18 * l * r;
  if (object.empty()) return {};
  glm::dvec3 lo(kInfinity), hi(-kInfinity);
  const glm::dmat3 m(inst.to_world.linear);
  const glm::dvec3 b(inst.to_world.offset);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 p((c & 1 ? object.hi : object.lo).x, (c & 2 ? object.hi : object.lo).y,
                       (c & 4 ? object.hi : object.lo).z);
    const glm::dvec3 w = m * p + b;
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  double s = 0.0;
  for (int a = 0; a < 3; ++a) s = std::fmax(s, std::fmax(std::fabs(lo[a]), std::fabs(hi[a])));
  const double alpha = 0x1p-19 * l * (r * s + 2.0 * norm_inf(inst.to_object.offset));
  const double margin = alpha + 0x1p-20 * s;
  Bounds3 out;
  out.lo = glm::vec3(lo - margin);
  out.hi = glm::vec3(hi + margin);
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(out.lo[a]) || !std::isfinite(out.hi[a]))
      throw std::invalid_argument("two-level: an instance's world bounds overflow float");
  return out;
}

// One entry of the single-ray stack: a node and the fat ray's interval in its cell.
struct Entry {
  std::uint32_t node;
  double tmin, tmax;
};

// Descends front to back from e to a leaf, pushing the far children still needed (at most
// one per level, so the stack never overflows), and returns the leaf.
KdNode descend(const TopRay& tr, const KdNode* nodes, Entry e, Entry* stack, int& sp) {
  while (!nodes[e.node].is_leaf()) {
    const KdNode n = nodes[e.node];
    const int axis = n.axis();
    const bool neg = tr.negative[axis];
    const TopStep step = top_step(tr, axis, n.split(), neg, e.tmin, e.tmax);
    const std::uint32_t near = neg ? n.right_child() : n.left_child();
    const std::uint32_t far = neg ? n.left_child() : n.right_child();
    if (step.near && step.far) {
      stack[sp++] = {far, step.far_min, e.tmax};
      e = {near, e.tmin, step.near_max};
    } else if (step.near) {
      e = {near, e.tmin, step.near_max};
    } else {
      e = {far, step.far_min, e.tmax};
    }
  }
  return nodes[e.node];
}

}  // namespace

unsigned TwoLevelAccelerator::few_met(const Ray& clipped, TopRay& tr) const {
  // Each instance's box at the ray's time, looked up once for both tests.
  const Bounds3* box[kFewTopInstances];
  for (std::size_t j = 0; j < few_top_.size(); ++j) box[j] = &few_box(j, clipped.time);
  // Every box lies inside the top level's, so its norm serves them all.
  const two_level::SegmentBox sb = two_level::segment_box(clipped, beta_, extent_, top_norm_);
  unsigned met = (1u << few_top_.size()) - 1;
  if (sb.usable) {
    for (std::size_t j = 0; j < few_top_.size(); ++j)
      if (sb.misses(*box[j])) met &= ~(1u << j);
    if (met == 0) {
      tr.plan = TopPlan::Miss;
      return 0;
    }
  }
  setup_top_ray(clipped, top_.bounds(), beta_, extent_, tr);
  // A ray beyond the top level's error argument (two_level_ray.h) meets every instance.
  if (tr.plan == TopPlan::Scan) return (1u << few_top_.size()) - 1;
  if (tr.plan == TopPlan::Miss) return 0;
  for (unsigned m = met; m != 0; m &= m - 1)
    if (!fat_ray_meets_box(tr, *box[std::countr_zero(m)])) met &= ~(1u << std::countr_zero(m));
  return met;
}

bool TwoLevelAccelerator::meets_moving(std::uint32_t i, const two_level::TopRay& tr, float time) const {
  return fat_ray_meets_box(tr, piece_box(i, time));
}

TwoLevelAccelerator::TwoLevelAccelerator(const TriangleSoA& tris, const InstancedGeometry& geometry,
                                         std::string_view bottom, const KdBuildOptions& kd, Isa isa) {
  const auto start = std::chrono::steady_clock::now();
  if (bottom == "kdtree") {
    bottom_name_ = "kdtree";
    if (!cpu_supports(isa))
      throw std::invalid_argument("two-level: this CPU does not support the " + std::string(isa_name(isa)) +
                                  " instruction set");
  } else if (bottom == "brute") {
    bottom_name_ = "brute";
  } else {
    throw std::invalid_argument("two-level: unknown bottom-level accelerator '" + std::string(bottom) + "'");
  }
  validate(tris, geometry);
  two_level::validate_motions(geometry);

  const std::size_t mesh_count = geometry.meshes.size();
  std::vector<bool> used(mesh_count, false);
  for (const Instance& inst : geometry.instances) used[inst.mesh] = true;
  mesh_first_.resize(mesh_count);
  bottoms_.resize(mesh_count);
  kept_.resize(mesh_count);
  std::vector<Bounds3> object_boxes(mesh_count);
  for (std::size_t m = 0; m < mesh_count; ++m) mesh_first_[m] = geometry.meshes[m].first;
  // One mesh per task: each writes only its own slots, and every tree is the same for any
  // thread count, so the result is too. Freed memory goes back once, after all of them.
  KdBuildOptions mesh_kd = kd;
  mesh_kd.hand_back_memory = false;
  tbb::parallel_for(std::size_t(0), mesh_count, [&](std::size_t m) {
    if (!used[m]) return;
    auto local = std::make_unique<TriangleSoA>(copy_mesh(tris, geometry.meshes[m]));
    object_boxes[m] = finite_bounds(*local);
    if (bottom_name_ == "kdtree") {
      bottoms_[m] = std::make_unique<KdTree>(*local, mesh_kd, isa);
    } else {
      bottoms_[m] = std::make_unique<BruteForce>(*local);
      kept_[m] = std::move(local);
    }
  });
  if (kd.hand_back_memory) release_free_memory();

  instances_ = geometry.instances;
  motions_ = PreparedMotions(geometry);
  // Direct instances stay out of the top level (an empty box is left out of it).
  direct_.assign(instances_.size(), 0);
  for (std::uint32_t i = 0; i < instances_.size(); ++i)
    if (is_identity(instances_[i])) {
      direct_[i] = 1;
      direct_list_.push_back(i);
    }
  std::vector<Bounds3> boxes(instances_.size());
  piece_first_.assign(instances_.size(), 0);
  piece_count_.assign(instances_.size(), 0);
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    if (direct_[i]) continue;
    const Bounds3& object = object_boxes[instances_[i].mesh];
    double beta = 0.0, linear_norm = 0.0;
    if (instances_[i].motion == kNoHit) {
      boxes[i] = world_box(instances_[i], object, beta);
      linear_norm = norm_inf(instances_[i].to_world.linear);
    } else {
      two_level::ShutterBounds b = two_level::shutter_bounds(geometry, instances_[i], object);
      boxes[i] = b.box;
      piece_first_[i] = std::uint32_t(piece_boxes_.size());
      piece_count_[i] = std::uint32_t(b.pieces.size());
      piece_boxes_.insert(piece_boxes_.end(), b.pieces.begin(), b.pieces.end());
      beta = b.beta;
      linear_norm = b.linear_norm;
    }
    beta_ = std::fmax(beta_, beta);
    const glm::vec3 e = object.extent();
    const double largest = std::fmax(e.x, std::fmax(e.y, e.z));
    extent_ = std::fmax(extent_, largest * linear_norm);
  }
  top_ = TopLevelTree(boxes);
  top_norm_ = two_level::box_norm(top_.bounds());
  std::vector<std::uint32_t> in_top;
  for (std::uint32_t i = 0; i < instances_.size(); ++i)
    if (!boxes[i].empty()) in_top.push_back(i);
  if (in_top.size() <= kFewTopInstances) {
    few_top_ = in_top;
    for (std::uint32_t i : few_top_) few_top_boxes_.push_back(boxes[i]);
  }
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

TwoLevelAccelerator::~TwoLevelAccelerator() = default;

std::size_t TwoLevelAccelerator::bottom_count() const {
  std::size_t n = 0;
  for (const auto& b : bottoms_) n += b ? 1 : 0;
  return n;
}

void TwoLevelAccelerator::visit(std::uint32_t i, const Ray& ray, Hit& best) const {
  Hit h = bottoms_[instances_[i].mesh]->intersect(entered(i, ray, best));
  if (!h.valid()) return;
  h.prim += mesh_first_[instances_[i].mesh];
  h.instance = i;
  best = h;
}

bool TwoLevelAccelerator::blocks(std::uint32_t i, const Ray& ray) const {
  return bottoms_[instances_[i].mesh]->occluded(entered(i, ray, Hit{}));
}

Hit TwoLevelAccelerator::intersect(const Ray& ray) const {
  Hit best;
  for (std::uint32_t i : direct_list_) visit(i, ray, best);
  intersect_top(ray, best);
  return best;
}

// A hit that beats `best` lies at or before best.t, so the top level clips the ray there.
void TwoLevelAccelerator::intersect_top(const Ray& ray, Hit& best) const {
  if (top_.bounds().empty()) return;
  Ray clipped = ray;
  if (best.valid()) clipped.tfar = two_level::smaller(best.t, clipped.tfar);  // keeps a NaN tfar (Scan)
  if (!few_top_.empty()) {  // each instance in turn, against its own box
    TopRay tr;
    for (unsigned met = few_met(clipped, tr); met != 0; met &= met - 1) visit(few_top_[std::countr_zero(met)], ray, best);
    return;
  }
  if (two_level::segment_misses(clipped, top_.bounds(), beta_, extent_)) return;
  const TopRay tr = setup_top_ray(clipped, top_.bounds(), beta_, extent_);
  if (tr.plan == TopPlan::Scan) {
    for (std::uint32_t i = 0; i < instances_.size(); ++i)
      if (!direct_[i]) visit(i, ray, best);
    return;
  }
  if (tr.plan == TopPlan::Miss) return;

  Entry stack[kTopLevelStackSize];
  two_level::Mailbox mailbox;
  int sp = 0;
  stack[sp++] = {0, tr.tmin, tr.tmax};
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  while (sp > 0) {
    const Entry e = stack[--sp];
    // Entries are not sorted by entry distance (fat intervals overlap), so skip, not stop.
    if (best.valid() && double(best.t) < lowest_hit_in_cell(tr, e.tmin)) continue;
    const KdNode leaf = descend(tr, nodes, e, stack, sp);
    for (std::uint32_t k = 0; k < leaf.count(); ++k) {
      const std::uint32_t i = items[leaf.first_slot() + k];
      if (mailbox.enter(i, 1) != 0 && (instances_[i].motion == kNoHit || meets_moving(i, tr, ray.time)))
        visit(i, ray, best);
    }
  }
}

bool TwoLevelAccelerator::occluded(const Ray& ray) const {
  for (std::uint32_t i : direct_list_)
    if (blocks(i, ray)) return true;
  return occluded_top(ray);
}

bool TwoLevelAccelerator::occluded_top(const Ray& ray) const {
  if (top_.bounds().empty()) return false;
  if (!few_top_.empty()) {
    TopRay tr;
    for (unsigned met = few_met(ray, tr); met != 0; met &= met - 1)
      if (blocks(few_top_[std::countr_zero(met)], ray)) return true;
    return false;
  }
  if (two_level::segment_misses(ray, top_.bounds(), beta_, extent_)) return false;
  const TopRay tr = setup_top_ray(ray, top_.bounds(), beta_, extent_);
  if (tr.plan == TopPlan::Scan) {
    for (std::uint32_t i = 0; i < instances_.size(); ++i)
      if (!direct_[i] && blocks(i, ray)) return true;
    return false;
  }
  if (tr.plan == TopPlan::Miss) return false;

  Entry stack[kTopLevelStackSize];
  two_level::Mailbox mailbox;
  int sp = 0;
  stack[sp++] = {0, tr.tmin, tr.tmax};
  const KdNode* nodes = top_.nodes().data();
  const std::uint32_t* items = top_.items().data();
  while (sp > 0) {
    const Entry e = stack[--sp];
    const KdNode leaf = descend(tr, nodes, e, stack, sp);
    for (std::uint32_t k = 0; k < leaf.count(); ++k) {
      const std::uint32_t i = items[leaf.first_slot() + k];
      if (mailbox.enter(i, 1) != 0 &&
          (instances_[i].motion == kNoHit || meets_moving(i, tr, ray.time)) && blocks(i, ray))
        return true;
    }
  }
  return false;
}

std::size_t TwoLevelAccelerator::memory_bytes() const {
  std::size_t bytes = top_.memory_bytes() + instances_.capacity() * sizeof(Instance) +
                      (piece_first_.capacity() + piece_count_.capacity()) * sizeof(std::uint32_t) +
                      few_top_.capacity() * sizeof(std::uint32_t) +
                      few_top_boxes_.capacity() * sizeof(Bounds3) +
                      piece_boxes_.capacity() * sizeof(Bounds3) + direct_.capacity() +
                      direct_list_.capacity() * sizeof(std::uint32_t) +
                      mesh_first_.capacity() * sizeof(std::uint32_t) +
                      bottoms_.capacity() * sizeof(std::unique_ptr<Accelerator>);
  for (const auto& b : bottoms_)
    if (b) bytes += b->memory_bytes();
  bytes += motions_.memory_bytes();
  bytes += kept_.capacity() * sizeof(std::unique_ptr<TriangleSoA>);
  for (const auto& t : kept_)
    if (t) bytes += 9 * t->size() * sizeof(float);
  return bytes;
}

}  // namespace lancer
