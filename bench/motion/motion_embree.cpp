// Embree 3 calls for lancer-motion-bench (built only when CMake finds Embree; see motion_embree.h).
#include "motion_embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "embree_rays.h"
#include "simd/isa.h"

namespace lancer::bench {

namespace {

// The affine x -> linear x + offset as Embree's column-major 3x4 matrix.
std::array<float, 12> column_major(const glm::mat3& linear, const glm::vec3& offset) {
  std::array<float, 12> m{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[static_cast<std::size_t>(3 * c + r)] = linear[c][r];
  for (int r = 0; r < 3; ++r) m[static_cast<std::size_t>(9 + r)] = offset[r];
  return m;
}

// Whether the key's stretch is diagonal up to float rounding (1e-6 of its largest entry).
bool diagonal_stretch(const MotionKey& key) {
  const glm::mat3& s = key.stretch;
  const float scale = std::max({std::abs(s[0][0]), std::abs(s[1][1]), std::abs(s[2][2])});
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (r != c && std::abs(s[c][r]) > 1e-6f * scale) return false;
  return true;
}

}  // namespace

bool motion_embree_available() { return true; }

std::string motion_embree_description() {
  RTCDevice d = rtcNewDevice(nullptr);
  if (!d) return "Embree 3: rtcNewDevice failed";
  const std::string line = "Embree " + std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) +
                           "." + std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
                           std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_PATCH)) +
                           ", ISA capped at " + embree_config_isa(best_supported_isa());
  rtcReleaseDevice(d);
  return line;
}

struct EmbreeMotionScene::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  std::vector<RTCScene> meshes;              // per mesh, its own committed scene
  std::vector<std::uint32_t> instance_first;  // per instance, its mesh's first triangle
  std::size_t quaternion_instances = 0, matrix_instances = 0;
  double build_ms = 0.0;
  mutable std::mutex error_mutex;
  std::string first_error;

  ~Impl() {
    if (top) rtcReleaseScene(top);
    for (RTCScene s : meshes) rtcReleaseScene(s);
    if (device) rtcReleaseDevice(device);
  }

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex);
    if (self->first_error.empty())
      self->first_error =
          "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "(no message)");
  }

  // Triangles [first, first + count) of `tris` as one triangle geometry (corners unshared).
  RTCGeometry triangles(const TriangleSoA& tris, std::size_t first, std::size_t count) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), count));
    if (v == nullptr || idx == nullptr) return g;  // the error callback has the reason
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t k = 0; k < 3; ++k) {
        const glm::vec3 p = tris.vertex(first + i, static_cast<int>(k));
        std::copy(&p.x, &p.x + 3, v + 3 * (3 * i + k));
        idx[3 * i + k] = static_cast<std::uint32_t>(3 * i + k);
      }
    rtcCommitGeometry(g);
    return g;
  }

  RTCScene new_scene() const {
    RTCScene s = rtcNewScene(device);
    rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_HIGH);
    return s;
  }

  // Instance `inst` of the scene, still or with one time step per motion key.
  RTCGeometry instance(const InstancedGeometry& geometry, const Instance& inst) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, meshes[inst.mesh]);
    if (inst.motion == kNoHit) {
      const std::array<float, 12> m = column_major(inst.to_world.linear, inst.to_world.offset);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
    } else {
      const std::vector<MotionKey>& keys = geometry.motions[inst.motion].keys;
      rtcSetGeometryTimeStepCount(g, static_cast<unsigned>(keys.size()));
      const bool quaternion = std::all_of(keys.begin(), keys.end(), diagonal_stretch);
      ++(quaternion ? quaternion_instances : matrix_instances);
      glm::quat previous = keys.front().rotation;
      for (std::size_t step = 0; step < keys.size(); ++step) {
        const MotionKey& key = keys[step];
        if (quaternion) {
          const glm::quat q = glm::dot(previous, key.rotation) < 0.0f ? -key.rotation : key.rotation;
          previous = q;
          RTCQuaternionDecomposition d;
          rtcInitQuaternionDecomposition(&d);
          rtcQuaternionDecompositionSetScale(&d, key.stretch[0][0], key.stretch[1][1], key.stretch[2][2]);
          rtcQuaternionDecompositionSetQuaternion(&d, q.w, q.x, q.y, q.z);
          rtcQuaternionDecompositionSetTranslation(&d, key.translation.x, key.translation.y, key.translation.z);
          rtcSetGeometryTransformQuaternion(g, static_cast<unsigned>(step), &d);
        } else {
          const Instance at_key = instance_from_key(inst.mesh, key);
          const std::array<float, 12> m = column_major(at_key.to_world.linear, at_key.to_world.offset);
          rtcSetGeometryTransform(g, static_cast<unsigned>(step), RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
        }
      }
    }
    rtcCommitGeometry(g);
    return g;
  }
};

EmbreeMotionScene::EmbreeMotionScene(const Scene& scene, int threads) : impl_(std::make_unique<Impl>()) {
  const std::string config = std::string("max_isa=") + embree_config_isa(best_supported_isa()) +
                             ",threads=" + std::to_string(std::max(threads, 0));
  impl_->device = rtcNewDevice(config.c_str());
  if (!impl_->device)
    throw std::runtime_error("Embree: rtcNewDevice(\"" + config + "\") failed (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl_->device, &Impl::on_error, impl_.get());

  const auto start = std::chrono::steady_clock::now();
  impl_->top = impl_->new_scene();
  const InstancedGeometry& geometry = scene.instancing;
  if (geometry.empty()) {
    RTCGeometry g = impl_->triangles(scene.triangles, 0, scene.triangle_count());
    rtcAttachGeometry(impl_->top, g);
    rtcReleaseGeometry(g);
  } else {
    for (const MeshRange& mesh : geometry.meshes) {
      RTCScene s = impl_->new_scene();
      impl_->meshes.push_back(s);
      RTCGeometry g = impl_->triangles(scene.triangles, mesh.first, mesh.count);
      rtcAttachGeometry(s, g);
      rtcReleaseGeometry(g);
      rtcCommitScene(s);
    }
    check_errors();
    for (std::size_t i = 0; i < geometry.instances.size(); ++i) {
      const Instance& inst = geometry.instances[i];
      impl_->instance_first.push_back(geometry.meshes[inst.mesh].first);
      RTCGeometry g = impl_->instance(geometry, inst);
      rtcAttachGeometryByID(impl_->top, g, static_cast<unsigned>(i));
      rtcReleaseGeometry(g);
    }
  }
  check_errors();
  rtcCommitScene(impl_->top);
  impl_->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  check_errors();
}

EmbreeMotionScene::~EmbreeMotionScene() = default;

double EmbreeMotionScene::build_ms() const { return impl_->build_ms; }
std::size_t EmbreeMotionScene::quaternion_instances() const { return impl_->quaternion_instances; }
std::size_t EmbreeMotionScene::matrix_instances() const { return impl_->matrix_instances; }

void EmbreeMotionScene::check_errors() const {
  std::lock_guard<std::mutex> lock(impl_->error_mutex);
  if (!impl_->first_error.empty()) throw std::runtime_error(impl_->first_error);
}

void EmbreeMotionScene::intersect(bool single, const Ray* rays, Hit* hits, std::size_t count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Embree's answer in Lancer's numbering.
  const auto to_hit = [&](unsigned geom, unsigned inst, unsigned prim, float t, float u, float v) {
    if (geom == RTC_INVALID_GEOMETRY_ID) return Hit{};
    if (inst == RTC_INVALID_GEOMETRY_ID) return Hit{t, prim, u, v, kNoHit};
    return Hit{t, impl_->instance_first[inst] + prim, u, v, inst};
  };
  if (single) {
    for (std::size_t i = 0; i < count; ++i) {
      RTCRayHit rh;
      set_ray(rh.ray, rays[i]);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(impl_->top, &context, &rh);
      hits[i] = to_hit(rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.ray.tfar, rh.hit.u, rh.hit.v);
    }
    return;
  }
  for (std::size_t first = 0; first < count; first += 16) {
    const std::size_t k = std::min<std::size_t>(16, count - first);
    const ValidMask16 valid(k);
    RTCRayHit16 rh;
    for (std::size_t i = 0; i < k; ++i) {
      set_ray16(rh.ray, i, rays[first + i]);
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid.lanes.data(), impl_->top, &context, &rh);
    for (std::size_t i = 0; i < k; ++i)
      hits[first + i] = to_hit(rh.hit.geomID[i], rh.hit.instID[0][i], rh.hit.primID[i], rh.ray.tfar[i], rh.hit.u[i],
                               rh.hit.v[i]);
  }
}

}  // namespace lancer::bench
