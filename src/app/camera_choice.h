// Which camera a command renders or shoots rays from: the one the command line describes
// (--eye/--look-at), else a scene camera (--camera, default the first), else a camera
// framing the whole scene. Shared by `lancer render` and `lancer rays`.
#pragma once

#include <optional>

#include <glm/vec3.hpp>

#include "render/camera.h"
#include "scene/scene.h"

namespace lancer {

struct CameraRequest {
  std::optional<int> camera;  // glTF camera index (CameraDesc::index)
  std::optional<glm::vec3> eye, look_at, up;
  std::optional<float> fov_degrees;  // vertical
};

// The camera for a width x height image. When !height_given, `height` is first set to
// the width, then to the width over the scene camera's aspect ratio when it has one.
// Throws std::invalid_argument for --eye without --look-at (or the reverse) and for a
// camera index the scene does not have.
PinholeCamera choose_camera(const CameraRequest& request, const Scene& scene, int width, int& height,
                            bool height_given);

}  // namespace lancer
