// Embree 3 calls for lancer-bench (built only when CMake finds Embree; see embree_tracer.h).
#include "embree_tracer.h"

#include <embree3/rtcore.h>

#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>

#include "embree_rays.h"

namespace lancer::bench {

namespace {

RTCIntersectContext make_context(EmbreeCall call) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  if (call == EmbreeCall::Intersect16Coherent || call == EmbreeCall::Occluded16Coherent)
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  return context;
}

}  // namespace

std::string_view embree_call_name(EmbreeCall call) {
  switch (call) {
    case EmbreeCall::Intersect1: return "rtcIntersect1";
    case EmbreeCall::Intersect16: return "rtcIntersect16";
    case EmbreeCall::Intersect16Coherent: return "rtcIntersect16 (coherent)";
    case EmbreeCall::Occluded1: return "rtcOccluded1";
    case EmbreeCall::Occluded16: return "rtcOccluded16";
    case EmbreeCall::Occluded16Coherent: return "rtcOccluded16 (coherent)";
  }
  return "unknown";
}

bool embree_call_is_occlusion(EmbreeCall call) {
  return call == EmbreeCall::Occluded1 || call == EmbreeCall::Occluded16 || call == EmbreeCall::Occluded16Coherent;
}

bool embree_available() { return true; }

std::string_view embree_isa_cap(Isa isa) { return embree_config_isa(isa); }

std::string embree_description() {
  RTCDevice d = rtcNewDevice(nullptr);
  if (!d) return "Embree 3: rtcNewDevice failed";
  const std::string line = "Embree " + std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) +
                           "." + std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
                           std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_PATCH)) +
                           ", native 16-ray packets: " +
                           (rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) ? "yes" : "no");
  rtcReleaseDevice(d);
  return line;
}

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<std::int64_t> allocated{0};
  double build_ms = 0.0;
  std::int64_t memory_bytes = 0;
  mutable std::mutex error_mutex;
  std::string first_error;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex);
    if (self->first_error.empty())
      self->first_error =
          "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "(no message)");
  }

  // Embree reports allocations as positive byte counts and releases as negative ones.
  static bool on_memory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<Impl*>(user)->allocated.fetch_add(static_cast<std::int64_t>(bytes), std::memory_order_relaxed);
    return true;
  }
};

EmbreeScene::EmbreeScene(const TriangleSoA& tris, Isa isa, int threads) : impl_(std::make_unique<Impl>()) {
  const std::string config =
      "max_isa=" + std::string(embree_isa_cap(isa)) + ",threads=" + std::to_string(threads > 0 ? threads : 0);
  impl_->device = rtcNewDevice(config.c_str());
  if (!impl_->device)
    throw std::runtime_error("Embree: rtcNewDevice(\"" + config + "\") failed (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl_->device, &Impl::on_error, impl_.get());
  rtcSetDeviceMemoryMonitorFunction(impl_->device, &Impl::on_memory, impl_.get());

  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
  const std::size_t n = tris.size();
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* idx = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), n));
  check_errors();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      float* p = v + 3 * (3 * i + static_cast<std::size_t>(k));
      p[0] = tris.x[k][i];
      p[1] = tris.y[k][i];
      p[2] = tris.z[k][i];
      idx[3 * i + static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(3 * i + static_cast<std::size_t>(k));
    }
  rtcCommitGeometry(g);
  rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  check_errors();

  const std::int64_t before = impl_->allocated.load();
  const auto start = std::chrono::steady_clock::now();
  rtcCommitScene(impl_->scene);
  impl_->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  impl_->memory_bytes = impl_->allocated.load() - before;
  check_errors();
}

EmbreeScene::~EmbreeScene() = default;

double EmbreeScene::build_ms() const { return impl_->build_ms; }
std::int64_t EmbreeScene::memory_bytes() const { return impl_->memory_bytes; }

void EmbreeScene::check_errors() const {
  std::lock_guard<std::mutex> lock(impl_->error_mutex);
  if (!impl_->first_error.empty()) throw std::runtime_error(impl_->first_error);
}

void EmbreeScene::intersect(EmbreeCall call, const Ray* rays, Hit* hits, std::size_t count) const {
  RTCIntersectContext context = make_context(call);
  if (call == EmbreeCall::Intersect1) {
    for (std::size_t i = 0; i < count; ++i) {
      RTCRayHit rh;
      set_ray(rh.ray, rays[i]);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(impl_->scene, &context, &rh);
      Hit h;
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) h = Hit{rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v};
      hits[i] = h;
    }
    return;
  }
  if (call != EmbreeCall::Intersect16 && call != EmbreeCall::Intersect16Coherent)
    throw std::invalid_argument("EmbreeScene::intersect: not an intersect call");
  for (std::size_t first = 0; first < count; first += 16) {
    const std::size_t k = std::min<std::size_t>(16, count - first);
    const ValidMask16 valid(k);
    RTCRayHit16 rh;
    for (std::size_t i = 0; i < k; ++i) {
      set_ray16(rh.ray, i, rays[first + i]);
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid.lanes.data(), impl_->scene, &context, &rh);
    for (std::size_t i = 0; i < k; ++i) {
      Hit h;
      if (rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID)
        h = Hit{rh.ray.tfar[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]};
      hits[first + i] = h;
    }
  }
}

void EmbreeScene::occluded(EmbreeCall call, const Ray* rays, std::uint8_t* occluded, std::size_t count) const {
  RTCIntersectContext context = make_context(call);
  if (call == EmbreeCall::Occluded1) {
    for (std::size_t i = 0; i < count; ++i) {
      RTCRay r;
      set_ray(r, rays[i]);
      rtcOccluded1(impl_->scene, &context, &r);
      occluded[i] = r.tfar < 0.0f ? 1 : 0;  // Embree sets tfar to -inf on an occluded ray
    }
    return;
  }
  if (call != EmbreeCall::Occluded16 && call != EmbreeCall::Occluded16Coherent)
    throw std::invalid_argument("EmbreeScene::occluded: not an occluded call");
  for (std::size_t first = 0; first < count; first += 16) {
    const std::size_t k = std::min<std::size_t>(16, count - first);
    const ValidMask16 valid(k);
    RTCRay16 r;
    for (std::size_t i = 0; i < k; ++i) set_ray16(r, i, rays[first + i]);
    rtcOccluded16(valid.lanes.data(), impl_->scene, &context, &r);
    for (std::size_t i = 0; i < k; ++i) occluded[first + i] = r.tfar[i] < 0.0f ? 1 : 0;
  }
}

}  // namespace lancer::bench
