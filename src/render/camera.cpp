#include "render/camera.h"

#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace lancer {

PinholeCamera PinholeCamera::look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up,
                                     float vfov, int width, int height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");
  if (!(vfov > 0.0f && vfov < 3.14159265f)) throw std::invalid_argument("camera: field of view must be in (0, 180) degrees");
  const glm::vec3 view = target - eye;
  if (!(glm::length(view) > 0.0f)) throw std::invalid_argument("camera: eye and look-at point coincide");
  const glm::vec3 f = glm::normalize(view);
  const glm::vec3 side = glm::cross(f, up);
  if (!(glm::length(side) > 1e-6f * glm::length(up))) throw std::invalid_argument("camera: up is parallel to the view direction");
  const glm::vec3 right = glm::normalize(side);
  const glm::vec3 true_up = glm::cross(right, f);

  const float tan_half = std::tan(0.5f * vfov);
  PinholeCamera cam;
  cam.origin_ = eye;
  cam.forward_ = f;
  cam.x_axis_ = right * (tan_half * static_cast<float>(width) / static_cast<float>(height));
  cam.y_axis_ = -true_up * tan_half;
  cam.width_ = width;
  cam.height_ = height;
  return cam;
}

PinholeCamera PinholeCamera::from_desc(const CameraDesc& desc, int width, int height) {
  const glm::mat4& m = desc.camera_to_world;
  const glm::vec3 eye(m[3]);
  const glm::vec3 forward = -glm::vec3(m[2]);
  const glm::vec3 up(m[1]);
  return look_at(eye, eye + forward, up, desc.yfov, width, height);
}

PinholeCamera PinholeCamera::framing(const Bounds3& box, int width, int height) {
  constexpr float kFov = 0.7853981634f;  // 45 degrees
  const glm::vec3 center = box.empty() ? glm::vec3(0.0f) : box.center();
  float radius = 0.5f * glm::length(box.extent());
  if (!(radius > 0.0f)) radius = 1.0f;
  // Fit the bounding sphere in the narrower of the two fields of view.
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float half = aspect < 1.0f ? std::atan(std::tan(0.5f * kFov) * aspect) : 0.5f * kFov;
  const float distance = radius / std::sin(half);
  return look_at(center + glm::vec3(0.0f, 0.0f, distance), center, glm::vec3(0.0f, 1.0f, 0.0f), kFov, width,
                 height);
}

Ray PinholeCamera::generate(float i, float j) const {
  const float sx = 2.0f * (i / static_cast<float>(width_) - 0.5f);
  const float sy = 2.0f * (j / static_cast<float>(height_) - 0.5f);
  Ray r;
  r.org = origin_;
  r.dir = glm::normalize(forward_ + sx * x_axis_ + sy * y_axis_);
  r.tnear = 0.0f;
  r.tfar = kInfinity;
  return r;
}

}  // namespace lancer
