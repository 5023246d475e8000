// The pinhole camera of the course: origin o, optical axis f, image axes x and y scaled to
// the field of view. For continuous pixel coordinates (i, j), i in [0, W] to the right and
// j in [0, H] downwards,  d = f + 2(i/W - 0.5) x + 2(j/H - 0.5) y,  normalised.
//
// Optionally a thin lens (Kolb, Mitchell & Hanrahan 1995; Pharr, Jakob & Humphreys, PBR
// 4th ed., section 5.2.3): a disk of radius aperture_radius around o, perpendicular to f,
// focused on the plane at focus_distance along f. A ray through pixel (i, j) leaves from a
// point on the disk (lens_u mapped by the concentric map) towards the point where the
// pinhole ray through (i, j) meets the focus plane, o + focus_distance * d (d unnormalised,
// d.f = 1), so everything on that plane is sharp. An infinite focus distance keeps every
// ray parallel to the pinhole ray. With aperture 0 the camera is exactly the pinhole.
//
// Or orthographic (a glTF "orthographic" camera): every ray runs along f, from the point
// o + 2(i/W - 0.5) x + 2(j/H - 0.5) y of the image plane through o, x and y the view's
// half extents in scene units. It has no lens.
#pragma once

#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "accel/triangle_soa.h"
#include "scene/scene.h"

namespace lancer {

// Where light leaving a point reaches the image (light tracing, render/light_tracer.h).
struct CameraPoint {
  bool valid = false;       // false: the point is behind the camera or outside the image
  glm::vec3 lens{0.0f};     // the point on the lens the light goes to (the origin for a pinhole)
  int x = 0, y = 0;         // the pixel it lands in
  // 1 / (A r^2 cos^3 theta): A the pixel's area on the image plane at distance 1, r the
  // distance from the lens point, theta the angle of the way to it from the optical axis.
  // Times the cosine at a surface point, the change of measure from its area to the pixel's.
  float importance = 0.0f;
};

class PinholeCamera {
 public:
  // vfov in radians, the full vertical field of view. Throws std::invalid_argument when
  // eye == target, up is parallel to the view direction, the fov is outside (0, pi), or
  // the image size is not positive.
  static PinholeCamera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float vfov,
                               int width, int height);
  // A glTF camera (looks down its local -z, +y up) with its yfov, and its thin lens when
  // the description has an aperture (focus at infinity unless a focus distance is given).
  static PinholeCamera from_desc(const CameraDesc& desc, int width, int height);
  // Looks at the box's centre from a three-quarter view (from the front, +z, turned 45
  // degrees towards +x and raised 30 degrees), far enough to see all of it: a model lying
  // flat in any of the axis planes is seen at an angle, not edge-on.
  static PinholeCamera framing(const Bounds3& box, int width, int height);

  // A primary ray through continuous pixel position (i, j); dir is unit length. Always
  // the pinhole ray from origin(), whatever the lens.
  Ray generate(float i, float j) const;
  // The same through the thin lens at lens_u in [0, 1)^2; identical to generate(i, j)
  // (bit for bit) when the aperture radius is 0.
  Ray generate(float i, float j, glm::vec2 lens_u) const;

  // The adjoint of generate(i, j, lens_u): the pixel whose rays through the lens point of
  // lens_u reach p, and the camera's importance there (Veach 1997, sec. 10.2.1; PBR 4th ed.,
  // 5.4). With a thin lens the ray leaves the lens point towards p's image on the focus
  // plane, as generate() makes it. Not for an orthographic camera (its rays are one
  // direction: no point connects to it).
  CameraPoint connect(const glm::vec3& p, glm::vec2 lens_u) const;
  // A pixel's area on the image plane at distance 1 (2|x| by 2|y| over the pixels).
  float pixel_area() const {
    return 4.0f * glm::length(x_axis_) * glm::length(y_axis_) /
           (static_cast<float>(width_) * static_cast<float>(height_));
  }

  // aperture_radius in scene units (0: pinhole); focus_distance along the optical axis,
  // in scene units, > 0, may be +infinity. Throws std::invalid_argument otherwise, and for
  // an orthographic camera with an aperture.
  void set_thin_lens(float aperture_radius, float focus_distance);
  // Motion blur: the shutter stays open for a while, and each camera sample gets a time in
  // it (Ray::time, stratified per pixel: PrimaryBlock). Closed (false): every ray at 0.
  void set_shutter_open(bool open) { shutter_open_ = open; }
  bool shutter_open() const { return shutter_open_; }
  // A camera that moves while the shutter is open: camera_to_world at evenly spaced times
  // over it (CameraDesc::motion, the first at the opening, where the camera was built).
  // Empty: still. moved() carries a ray made as at the opening along that motion to its
  // time (Ray::time), with instance_at's interpolation.
  void set_motion(const std::vector<MotionKey>& keys);
  bool moves() const { return !motion_.motions.empty(); }
  Ray moved(const Ray& ray) const;
  bool orthographic() const { return orthographic_; }
  float aperture_radius() const { return aperture_radius_; }
  float focus_distance() const { return focus_distance_; }

  const glm::vec3& origin() const { return origin_; }
  const glm::vec3& forward() const { return forward_; }
  const glm::vec3& x_axis() const { return x_axis_; }
  const glm::vec3& y_axis() const { return y_axis_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  // CameraPoint::importance of p seen from the lens point `lens` (p in front of the lens).
  float importance(const glm::vec3& lens, const glm::vec3& p) const;

  glm::vec3 origin_{0.0f};
  glm::vec3 forward_{0.0f, 0.0f, -1.0f};  // f: unit optical axis
  glm::vec3 x_axis_{1.0f, 0.0f, 0.0f};    // x: right, length tan(hfov/2)
  glm::vec3 y_axis_{0.0f, -1.0f, 0.0f};   // y: down, length tan(vfov/2)
  int width_ = 1;
  int height_ = 1;
  float aperture_radius_ = 0.0f;
  float focus_distance_ = std::numeric_limits<float>::infinity();
  bool orthographic_ = false;  // x_axis_ and y_axis_: the half extents in scene units
  bool shutter_open_ = false;
  InstancedGeometry motion_;  // one motion when the camera moves, else none
  Instance moving_, opening_;  // the camera as a moving instance, and where it opens
};

// Shirley & Chiu's concentric map ("A Low Distortion Map Between Disk and Square", JGT
// 2(3), 1997): [0, 1)^2 onto the unit disk, area-preserving, squares to rings.
glm::vec2 concentric_disk(glm::vec2 u);

}  // namespace lancer
