// lancer-motion-bench without Embree: the Lancer side runs, Embree's is reported absent.
#include <stdexcept>

#include "motion_embree.h"

namespace lancer::bench {

struct EmbreeMotionScene::Impl {};

bool motion_embree_available() { return false; }
std::string motion_embree_description() { return "Embree absent (not found when CMake ran)"; }

EmbreeMotionScene::EmbreeMotionScene(const Scene&, int) {
  throw std::runtime_error("lancer-motion-bench was built without Embree");
}
EmbreeMotionScene::~EmbreeMotionScene() = default;
void EmbreeMotionScene::intersect(bool, const Ray*, Hit*, std::size_t) const {}
double EmbreeMotionScene::build_ms() const { return 0.0; }
std::size_t EmbreeMotionScene::quaternion_instances() const { return 0; }
std::size_t EmbreeMotionScene::matrix_instances() const { return 0; }
void EmbreeMotionScene::check_errors() const {}

}  // namespace lancer::bench
