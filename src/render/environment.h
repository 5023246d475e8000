// Distant light arriving from every direction: a constant colour, or an equirectangular
// (latitude-longitude) radiance map, with importance sampling.
//
// Directions are glTF world directions (+y up, right-handed). For a map of W x H pixels:
//   phi   = atan2(x, -z)  in (-pi, pi]: 0 towards -z, pi/2 towards +x
//   theta = acos(y)       in [0, pi]:   0 towards +y
//   u = 0.5 + phi / (2 pi),   v = theta / pi,   pixel (floor(u W), floor(v H)).
// So the image centre (u = 0.5) lies towards -z, where a default glTF camera looks, the
// top row is +y and the bottom row -y, the left and right edges meet towards +z, and u
// grows towards +x: seen from inside, facing -z with +y up, the map is not mirrored.
// Lookup is nearest-pixel (no filtering), which makes the importance sampling exactly
// proportional to the map's luminance times sin(theta) within each pixel.
//
// Sampling (Pharr, Jakob & Humphreys, PBR 4th ed., section 12.5.2): a piecewise-constant
// density over (u, v) with weights luminance(pixel) * sin(theta at the row's centre), the
// row picked by the marginal and the pixel by the row's conditional; the (u, v) density p
// becomes the solid-angle density p / (2 pi^2 sin(theta)). sample() returns radiance()
// and pdf() of the direction it returns. Pixels of zero luminance are never sampled
// (pdf 0), and nor are the poles, where the density is undefined.
// A constant environment is sampled uniformly over the sphere: pdf 1 / (4 pi).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/image.h"
#include "render/piecewise_constant.h"

namespace lancer {

struct EnvSample {
  glm::vec3 dir{0.0f, 1.0f, 0.0f};  // unit length, towards the environment
  glm::vec3 radiance{0.0f};         // arriving along -dir
  float pdf = 0.0f;                 // solid angle; 0 means the sample must be discarded
};

class Environment {
 public:
  // The same radiance from every direction. Throws std::invalid_argument unless every
  // component is finite and >= 0.
  explicit Environment(const glm::vec3& radiance);

  // An equirectangular map read with read_image (OpenEXR or Radiance .hdr for real
  // radiance; 8-bit PNG/JPEG are decoded from sRGB), every pixel multiplied by `scale`.
  // Throws ImageError naming the file when it cannot be read, or a pixel is NaN,
  // infinite or negative, or scale is not finite and >= 0.
  Environment(const std::filesystem::path& file, float scale);

  // The same from an image in memory; `name` is used in error messages.
  Environment(ImageRGB image, float scale, const std::string& name);

  // Radiance arriving along -dir (dir need not be unit length, must not be zero).
  glm::vec3 radiance(const glm::vec3& dir) const;

  // u in [0, 1)^2.
  EnvSample sample(glm::vec2 u) const;
  // Solid-angle density of sample() at dir (need not be unit length).
  float pdf(const glm::vec3& dir) const;

  bool is_constant() const { return !distribution_.has_value(); }
  // The map after scaling (empty for a constant environment).
  const ImageRGB& image() const { return image_; }

 private:
  glm::vec3 constant_{0.0f};
  ImageRGB image_;
  std::optional<Distribution2D> distribution_;
};

// Equirectangular mapping of the convention above, exposed for tests and tools.
// (u, v) in [0, 1]^2 -> unit direction.
glm::vec3 equirect_direction(double u, double v);
// Direction (any length > 0) -> (u, v) in [0, 1]^2.
glm::dvec2 equirect_uv(const glm::vec3& dir);

}  // namespace lancer
