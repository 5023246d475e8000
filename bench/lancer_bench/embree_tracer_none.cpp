// lancer-bench without Embree (CMake did not find it): the embree mode reports itself
// unavailable, and nothing here can be reached through the options.
#include <stdexcept>

#include "embree_tracer.h"

namespace lancer::bench {

namespace {
[[noreturn]] void missing() {
  throw std::runtime_error("this lancer-bench was built without Embree 3 (install libembree-dev and reconfigure)");
}
}  // namespace

std::string_view embree_call_name(EmbreeCall) { return "n/a"; }
bool embree_call_is_occlusion(EmbreeCall call) {
  return call == EmbreeCall::Occluded1 || call == EmbreeCall::Occluded16 || call == EmbreeCall::Occluded16Coherent;
}
bool embree_available() { return false; }
std::string embree_description() { return "Embree 3: not built in (CMake did not find it)"; }
std::string_view embree_isa_cap(Isa) { return "n/a"; }

struct EmbreeScene::Impl {};

EmbreeScene::EmbreeScene(const TriangleSoA&, Isa, int) { missing(); }
EmbreeScene::~EmbreeScene() = default;
double EmbreeScene::build_ms() const { missing(); }
std::int64_t EmbreeScene::memory_bytes() const { missing(); }
void EmbreeScene::intersect(EmbreeCall, const Ray*, Hit*, std::size_t) const { missing(); }
void EmbreeScene::occluded(EmbreeCall, const Ray*, std::uint8_t*, std::size_t) const { missing(); }
void EmbreeScene::check_errors() const { missing(); }

}  // namespace lancer::bench
