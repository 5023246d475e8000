// The pinhole camera of the course: origin o, optical axis f, image axes x and y scaled to
// the field of view. For continuous pixel coordinates (i, j), i in [0, W] to the right and
// j in [0, H] downwards,  d = f + 2(i/W - 0.5) x + 2(j/H - 0.5) y,  normalised.
#pragma once

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "accel/triangle_soa.h"
#include "scene/scene.h"

namespace lancer {

class PinholeCamera {
 public:
  // vfov in radians, the full vertical field of view. Throws std::invalid_argument when
  // eye == target, up is parallel to the view direction, the fov is outside (0, pi), or
  // the image size is not positive.
  static PinholeCamera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float vfov,
                               int width, int height);
  // A glTF camera (looks down its local -z, +y up) with its yfov.
  static PinholeCamera from_desc(const CameraDesc& desc, int width, int height);
  // Looks at the box from its +z side (the glTF "front"), far enough to see all of it.
  static PinholeCamera framing(const Bounds3& box, int width, int height);

  // A primary ray through continuous pixel position (i, j); dir is unit length.
  Ray generate(float i, float j) const;

  const glm::vec3& origin() const { return origin_; }
  const glm::vec3& forward() const { return forward_; }
  const glm::vec3& x_axis() const { return x_axis_; }
  const glm::vec3& y_axis() const { return y_axis_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  glm::vec3 origin_{0.0f};
  glm::vec3 forward_{0.0f, 0.0f, -1.0f};  // f: unit optical axis
  glm::vec3 x_axis_{1.0f, 0.0f, 0.0f};    // x: right, length tan(hfov/2)
  glm::vec3 y_axis_{0.0f, -1.0f, 0.0f};   // y: down, length tan(vfov/2)
  int width_ = 1;
  int height_ = 1;
};

}  // namespace lancer
