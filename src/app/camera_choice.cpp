#include "app/camera_choice.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lancer {

namespace {
constexpr double kDegrees = 3.14159265358979323846 / 180.0;
}  // namespace

PinholeCamera choose_camera(const CameraRequest& request, const Scene& scene, int width, int& height,
                            bool height_given) {
  if (!height_given) height = width;  // square unless the scene camera says otherwise
  if (request.eye || request.look_at) {
    if (!request.eye || !request.look_at) throw std::invalid_argument("--eye and --look-at must be given together");
    const float fov = static_cast<float>(request.fov_degrees.value_or(45.0f) * kDegrees);
    return PinholeCamera::look_at(*request.eye, *request.look_at, request.up.value_or(glm::vec3(0, 1, 0)), fov, width,
                                  height);
  }
  if (!scene.cameras.empty()) {
    const CameraDesc* chosen = &scene.cameras.front();
    if (request.camera) {
      // The file's camera numbers (CameraDesc::index), not the order the scene places them in.
      auto it = std::find_if(scene.cameras.begin(), scene.cameras.end(),
                             [&](const CameraDesc& c) { return c.index == *request.camera; });
      if (it == scene.cameras.end()) {
        std::string have;
        for (const CameraDesc& c : scene.cameras) have += (have.empty() ? "" : ", ") + std::to_string(c.index);
        throw std::invalid_argument("--camera " + std::to_string(*request.camera) +
                                    ": the scene places no such camera (it has camera(s) " + have + ")");
      }
      chosen = &*it;
    }
    CameraDesc desc = *chosen;
    if (!height_given && desc.aspect_ratio && *desc.aspect_ratio > 0.0f)
      height = std::max(1, static_cast<int>(std::lround(width / *desc.aspect_ratio)));
    if (request.fov_degrees) {
      if (desc.orthographic) throw std::invalid_argument("--fov: the chosen camera is orthographic (it has no field of view)");
      desc.yfov = static_cast<float>(*request.fov_degrees * kDegrees);
    }
    return PinholeCamera::from_desc(desc, width, height);
  }
  if (request.camera) throw std::invalid_argument("--camera given but the scene has no cameras");
  return PinholeCamera::framing(scene.bounds(), width, height);
}

}  // namespace lancer
