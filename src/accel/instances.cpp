#include "accel/instances.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace lancer {

namespace {

// The span from key a to key b: the slerp on the shorter arc (Shoemake 1985, in double)
// written as q(f) = cos(f theta) from + sin(f theta) across, `across` the unit quaternion
// orthogonal to `from` towards `to`: one sincos per time. Nearly equal rotations blend
// linearly, where dividing by sin(theta) would lose the result's precision.
MotionSpan make_span(const MotionKey& a, const MotionKey& b) {
  MotionSpan s;
  s.from = glm::normalize(glm::dquat(a.rotation));
  s.to = glm::normalize(glm::dquat(b.rotation));
  double c = glm::dot(s.from, s.to);
  if (c < 0.0) {
    s.to = -s.to;
    c = -c;
  }
  if (c < 0.9999) {
    s.theta = std::acos(c);
    s.across = (s.to - c * s.from) / std::sin(s.theta);
  }
  s.stretch_from = glm::dmat3(a.stretch);
  s.stretch_to = glm::dmat3(b.stretch);
  s.constant_stretch = s.stretch_from == s.stretch_to;
  if (s.constant_stretch) s.stretch_inverse = glm::inverse(s.stretch_from);  // only read then
  s.translation_from = glm::dvec3(a.translation);
  s.translation_to = glm::dvec3(b.translation);
  return s;
}

glm::dquat slerp(const MotionSpan& s, double f) {
  if (s.theta == 0.0) return glm::normalize((1.0 - f) * s.from + f * s.to);
  const double angle = f * s.theta;
  return glm::normalize(std::cos(angle) * s.from + std::sin(angle) * s.across);
}

// linear = rotation * stretch; its inverse is stretch^-1 * rotation^T (exact for the double
// values up to rounding: `rotation` must be unit, as mat3_cast of a quaternion a few ulps off
// unit length is off a rotation by as much).
// A stretch that is exactly the identity (a rigid motion's) multiplies nothing.
Instance from_parts(std::uint32_t mesh, const glm::dquat& rotation, const glm::dmat3& stretch,
                    const glm::dmat3& stretch_inverse, const glm::dvec3& translation) {
  const glm::dmat3 r = glm::mat3_cast(rotation);
  const bool rigid = stretch == glm::dmat3(1.0);
  const glm::dmat3 linear = rigid ? r : r * stretch;
  const glm::dmat3 inverse = rigid ? glm::transpose(r) : stretch_inverse * glm::transpose(r);
  Instance inst;
  inst.mesh = mesh;
  inst.to_world = Affine{glm::mat3(linear), glm::vec3(translation)};
  inst.to_object = Affine{glm::mat3(inverse), glm::vec3(-(inverse * translation))};
  return inst;
}

}  // namespace

// Normalised as the slerp normalises, so a key's transforms are the limit of its
// neighbours' (a continuous path, which the accelerator's shutter boxes rely on).
Instance instance_from_key(std::uint32_t mesh, const MotionKey& key) {
  const glm::dmat3 stretch(key.stretch);
  return from_parts(mesh, glm::normalize(glm::dquat(key.rotation)), stretch, glm::inverse(stretch),
                    glm::dvec3(key.translation));
}

namespace {

// The transform at fraction f of span s (keys a to b), f from key_time. On a key, exactly
// its transforms: the blend would round them differently (and may flip the sign of a zero).
Instance blend(const Instance& inst, const MotionKey& a, const MotionKey& b, const MotionSpan& s, double f) {
  Instance out;
  if (f == 0.0 || f == 1.0) {
    out = instance_from_key(inst.mesh, f == 0.0 ? a : b);
  } else {
    const glm::dvec3 translation = glm::mix(s.translation_from, s.translation_to, f);
    if (s.constant_stretch) {
      out = from_parts(inst.mesh, slerp(s, f), s.stretch_from, s.stretch_inverse, translation);
    } else {
      const glm::dmat3 stretch = (1.0 - f) * s.stretch_from + f * s.stretch_to;
      out = from_parts(inst.mesh, slerp(s, f), stretch, glm::inverse(stretch), translation);
    }
  }
  out.motion = inst.motion;
  return out;
}

// A per-thread memo of interpolated transforms. A path's rays all carry the path's time, so
// the accelerator entering a moving instance for its camera ray, bounce and shadow rays and
// the renderer drawing its hits ask for the same transform many times; an interpolation
// (two sines, matrix products, an acos without a prepared span) costs about as much as a
// bottom-level traversal. An entry is keyed by everything the result is a function of: the
// two keys' bits, the key count and time (which give the fraction), the mesh and the motion
// index. A hit therefore returns exactly the bits a computation would, whichever geometry,
// accelerator or caller asked first. No lock and no allocation: a fixed table per thread.
struct MovedMemo {
  static constexpr int kBits = 9;
  struct Entry {
    MotionKey a, b;
    std::uint32_t key_count = 0;  // 0: empty (motions have at least two keys)
    std::uint32_t time_bits = 0, mesh = 0, motion = 0;
    Instance value;
  };
  Entry entries[1 << kBits];
};
thread_local MovedMemo moved_memo;

bool same_bits(const MotionKey& x, const MotionKey& y) { return std::memcmp(&x, &y, sizeof(MotionKey)) == 0; }

// inst at `time`, which falls at k among its keys, from `span` (computed on a miss when
// null: instance_at has no prepared spans).
const Instance& moved(const Instance& inst, const std::vector<MotionKey>& keys, float time, const KeyTime& k,
                      const MotionSpan* span) {
  static_assert(sizeof(MotionKey) == 16 * sizeof(float), "MotionKey must hold no padding: entries compare its bytes");
  const MotionKey &a = keys[k.interval], &b = keys[k.interval + 1];
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(time);
  const std::uint32_t count = std::uint32_t(keys.size());
  const std::uint32_t hash = (bits ^ (inst.motion * 0x9E3779B1u) ^ (inst.mesh * 0x7FEB352Du)) * 0x85EBCA6Bu;
  MovedMemo::Entry& e = moved_memo.entries[hash >> (32 - MovedMemo::kBits)];
  if (e.key_count == count && e.time_bits == bits && e.mesh == inst.mesh && e.motion == inst.motion &&
      same_bits(e.a, a) && same_bits(e.b, b))
    return e.value;
  e.value = span ? blend(inst, a, b, *span, k.f) : blend(inst, a, b, make_span(a, b), k.f);
  e.a = a;
  e.b = b;
  e.key_count = count;
  e.time_bits = bits;
  e.mesh = inst.mesh;
  e.motion = inst.motion;
  return e.value;
}

}  // namespace

void forget_moved_instances() {
  for (MovedMemo::Entry& e : moved_memo.entries) e.key_count = 0;
}

Instance instance_at(const InstancedGeometry& geometry, const Instance& inst, float time) {
  if (inst.motion == kNoHit) return inst;
  const std::vector<MotionKey>& keys = geometry.motions[inst.motion].keys;
  return moved(inst, keys, time, key_time(keys.size(), time), nullptr);
}

PreparedMotions::PreparedMotions(const InstancedGeometry& geometry) {
  keys_.reserve(geometry.motions.size());
  spans_.reserve(geometry.motions.size());
  for (const InstanceMotion& m : geometry.motions) {
    keys_.push_back(m.keys);
    std::vector<MotionSpan>& spans = spans_.emplace_back();
    for (std::size_t i = 0; i + 1 < m.keys.size(); ++i) spans.push_back(make_span(m.keys[i], m.keys[i + 1]));
  }
}

const Instance& PreparedMotions::moving_at(const Instance& inst, float time) const {
  const std::vector<MotionKey>& keys = keys_[inst.motion];
  const KeyTime k = key_time(keys.size(), time);
  return moved(inst, keys, time, k, &spans_[inst.motion][k.interval]);
}

Instance PreparedMotions::at(const Instance& inst, float time) const {
  return inst.motion == kNoHit ? inst : moving_at(inst, time);
}

std::size_t PreparedMotions::memory_bytes() const {
  std::size_t bytes = keys_.capacity() * sizeof(keys_[0]) + spans_.capacity() * sizeof(spans_[0]);
  for (const auto& k : keys_) bytes += k.capacity() * sizeof(MotionKey);
  for (const auto& s : spans_) bytes += s.capacity() * sizeof(MotionSpan);
  return bytes;
}

}  // namespace lancer
