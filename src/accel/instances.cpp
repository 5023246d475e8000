#include "accel/instances.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace lancer {

namespace {

// Slerp from unit a to unit b on the shorter arc, in double (Shoemake 1985); nearly equal
// rotations blend linearly, where sin(theta) would lose the result's precision.
glm::dquat slerp_shorter(glm::dquat a, glm::dquat b, double f) {
  double c = glm::dot(a, b);
  if (c < 0.0) {
    b = -b;
    c = -c;
  }
  double wa = 1.0 - f, wb = f;
  if (c < 0.9999) {
    const double theta = std::acos(c), s = std::sin(theta);
    wa = std::sin((1.0 - f) * theta) / s;
    wb = std::sin(f * theta) / s;
  }
  return glm::normalize(wa * a + wb * b);
}

// `rotation` must be unit: mat3_cast of a quaternion a few ulps off unit length is off a
// rotation by as much.
Instance from_parts(std::uint32_t mesh, const glm::dquat& rotation, const glm::dmat3& stretch,
                    const glm::dvec3& translation) {
  const glm::dmat3 linear = glm::mat3_cast(rotation) * stretch;
  const glm::dmat3 inverse = glm::inverse(linear);
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
  return from_parts(mesh, glm::normalize(glm::dquat(key.rotation)), glm::dmat3(key.stretch),
                    glm::dvec3(key.translation));
}

Instance instance_at(const InstancedGeometry& geometry, const Instance& inst, float time) {
  if (inst.motion == kNoHit) return inst;
  const std::vector<MotionKey>& keys = geometry.motions[inst.motion].keys;
  const double t = std::clamp(std::isnan(time) ? 0.0 : double(time), 0.0, 1.0);
  const double x = t * double(keys.size() - 1);
  const std::size_t i = std::min(std::size_t(x), keys.size() - 2);
  const double f = x - double(i);
  const MotionKey &a = keys[i], &b = keys[i + 1];
  // On a key, exactly its transforms: the blend would round them differently (and may flip
  // the sign of a zero).
  if (f == 0.0 || f == 1.0) {
    Instance out = instance_from_key(inst.mesh, f == 0.0 ? a : b);
    out.motion = inst.motion;
    return out;
  }
  const glm::dvec3 translation = glm::mix(glm::dvec3(a.translation), glm::dvec3(b.translation), f);
  const glm::dmat3 stretch = (1.0 - f) * glm::dmat3(a.stretch) + f * glm::dmat3(b.stretch);
  Instance out = from_parts(inst.mesh, slerp_shorter(glm::dquat(a.rotation), glm::dquat(b.rotation), f), stretch,
                            translation);
  out.motion = inst.motion;
  return out;
}

}  // namespace lancer
