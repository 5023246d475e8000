#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "render/turn.h"

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
  if (desc.orthographic) {
    // The axes look_at builds, rescaled: ymag vertically (mirrored when negative) and, as
    // for a perspective camera's yfov, ymag times the image's aspect ratio horizontally,
    // mirrored when xmag is negative. The image's height follows xmag / ymag by default
    // (CameraDesc::aspect_ratio).
    PinholeCamera cam = look_at(eye, eye + forward, up, 0.5f * std::numbers::pi_v<float>, width, height);
    if (!(std::isfinite(desc.ymag) && desc.ymag != 0.0f && std::isfinite(desc.xmag) && desc.xmag != 0.0f))
      throw std::invalid_argument("camera: orthographic magnifications must be finite and non-zero");
    cam.orthographic_ = true;
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    cam.x_axis_ = glm::normalize(cam.x_axis_) * (aspect * std::abs(desc.ymag) * (desc.xmag < 0.0f ? -1.0f : 1.0f));
    cam.y_axis_ = glm::normalize(cam.y_axis_) * desc.ymag;
    cam.set_motion(desc.motion);
    return cam;
  }
  PinholeCamera cam = look_at(eye, eye + forward, up, desc.yfov, width, height);
  if (desc.aperture_radius)
    cam.set_thin_lens(*desc.aperture_radius, desc.focus_distance.value_or(std::numeric_limits<float>::infinity()));
  cam.set_motion(desc.motion);
  return cam;
}

void PinholeCamera::set_thin_lens(float aperture_radius, float focus_distance) {
  if (!(std::isfinite(aperture_radius) && aperture_radius >= 0.0f))
    throw std::invalid_argument("camera: aperture radius must be finite and >= 0");
  if (!(focus_distance > 0.0f)) throw std::invalid_argument("camera: focus distance must be positive");
  if (orthographic_ && aperture_radius > 0.0f)
    throw std::invalid_argument("camera: an orthographic camera has no lens (no aperture, no depth of field)");
  aperture_radius_ = aperture_radius;
  focus_distance_ = focus_distance;
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
  // 45 degrees from +z towards +x, 30 degrees up: (sin 45 cos 30, sin 30, cos 45 cos 30).
  const glm::vec3 towards_eye(0.6123724357f, 0.5f, 0.6123724357f);
  return look_at(center + distance * towards_eye, center, glm::vec3(0.0f, 1.0f, 0.0f), kFov, width, height);
}

Ray PinholeCamera::generate(float i, float j) const {
  const float sx = 2.0f * (i / static_cast<float>(width_) - 0.5f);
  const float sy = 2.0f * (j / static_cast<float>(height_) - 0.5f);
  Ray r;
  if (orthographic_) {
    r.org = origin_ + sx * x_axis_ + sy * y_axis_;
    r.dir = forward_;
  } else {
    r.org = origin_;
    r.dir = glm::normalize(forward_ + sx * x_axis_ + sy * y_axis_);
  }
  r.tnear = 0.0f;
  r.tfar = kInfinity;
  return r;
}

Ray PinholeCamera::generate(float i, float j, glm::vec2 lens_u) const {
  if (aperture_radius_ == 0.0f) return generate(i, j);
  const float sx = 2.0f * (i / static_cast<float>(width_) - 0.5f);
  const float sy = 2.0f * (j / static_cast<float>(height_) - 0.5f);
  const glm::vec3 d = forward_ + sx * x_axis_ + sy * y_axis_;  // d.f = 1
  const glm::vec2 lens = aperture_radius_ * concentric_disk(lens_u);
  Ray r;
  r.org = origin_ + lens.x * glm::normalize(x_axis_) + lens.y * glm::normalize(y_axis_);
  r.dir = std::isinf(focus_distance_) ? glm::normalize(d) : glm::normalize(origin_ + focus_distance_ * d - r.org);
  r.tnear = 0.0f;
  r.tfar = kInfinity;
  return r;
}

CameraPoint PinholeCamera::connect(const glm::vec3& p, glm::vec2 lens_u) const {
  CameraPoint c;
  if (orthographic_) return c;
  c.lens = origin_;
  if (aperture_radius_ > 0.0f) {
    const glm::vec2 lens = aperture_radius_ * concentric_disk(lens_u);
    c.lens = origin_ + lens.x * glm::normalize(x_axis_) + lens.y * glm::normalize(y_axis_);
  }
  const glm::vec3 w = p - c.lens;
  const float along = glm::dot(w, forward_);
  if (!(along > 0.0f)) return c;
  // The pinhole direction d (d.f = 1) of the pixel position: through the point where the
  // ray from the lens point meets the focus plane (the lens lies in the plane through the
  // origin perpendicular to f), or parallel to the ray for a focus at infinity.
  const glm::vec3 d = aperture_radius_ > 0.0f && !std::isinf(focus_distance_)
                          ? (c.lens - origin_ + w * (focus_distance_ / along)) / focus_distance_
                          : w / along;
  const float len_x = glm::dot(x_axis_, x_axis_), len_y = glm::dot(y_axis_, y_axis_);
  const float i = (0.5f * glm::dot(d, x_axis_) / len_x + 0.5f) * static_cast<float>(width_);
  const float j = (0.5f * glm::dot(d, y_axis_) / len_y + 0.5f) * static_cast<float>(height_);
  if (!(i >= 0.0f && i < static_cast<float>(width_) && j >= 0.0f && j < static_cast<float>(height_))) return c;
  c.x = std::min(static_cast<int>(i), width_ - 1);
  c.y = std::min(static_cast<int>(j), height_ - 1);
  c.importance = importance(c.lens, p);
  c.valid = std::isfinite(c.importance) && c.importance > 0.0f;
  return c;
}

float PinholeCamera::importance(const glm::vec3& lens, const glm::vec3& p) const {
  const glm::vec3 w = p - lens;
  const float along = glm::dot(w, forward_);
  if (!(along > 0.0f)) return 0.0f;
  // A direction at angle theta from f covers dA cos^3 theta of solid angle per unit area dA
  // of the image plane at distance 1.
  const float r2 = glm::dot(w, w);
  const float cos_theta = along / std::sqrt(r2);
  return 1.0f / (pixel_area() * r2 * cos_theta * cos_theta * cos_theta);
}

glm::vec2 concentric_disk(glm::vec2 u) {
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  // The square's four triangular quarters go to the disk's four quarter sectors; the
  // radius is the larger coordinate, the angle linear along each square ring.
  // The angle in turns: an eighth of a turn per unit of b / a.
  float r, turns;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    turns = 0.125f * (b / a);
  } else {
    r = b;
    turns = 0.25f - 0.125f * (a / b);
  }
  return r * turn_cos_sin(turns);
}

void PinholeCamera::set_motion(const std::vector<MotionKey>& keys) {
  motion_ = {};
  if (keys.empty()) return;
  if (keys.size() < 2) throw std::invalid_argument("camera motion: at least two keys");
  motion_.motions.push_back({keys});
  moving_ = instance_from_key(0, keys.front());
  moving_.motion = 0;
  opening_ = instance_from_key(0, keys.front());
}

Ray PinholeCamera::moved(const Ray& ray) const {
  if (!moves()) return ray;
  const Instance now = instance_at(motion_, moving_, ray.time);
  Ray out = ray;
  out.org = now.to_world.point(opening_.to_object.point(ray.org));
  out.dir = glm::normalize(now.to_world.vector(opening_.to_object.vector(ray.dir)));
  return out;
}

}  // namespace lancer
