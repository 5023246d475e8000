#include "render/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "render/color.h"
#include "render/image_io.h"

namespace lancer {

namespace {

constexpr double kPi = std::numbers::pi;

bool finite_non_negative(float v) { return std::isfinite(v) && v >= 0.0f; }

// Refuses what would poison every pixel sample: NaN, infinities, negative radiance.
void check_pixels(const ImageRGB& image, const std::string& name) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw ImageError(name, "environment map has no pixels or an inconsistent size");
  static const char* kChannel[3] = {"R", "G", "B"};
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    const float v = image.rgb[i];
    if (finite_non_negative(v)) continue;
    const std::size_t pixel = i / 3;
    const std::size_t x = pixel % static_cast<std::size_t>(image.width), y = pixel / static_cast<std::size_t>(image.width);
    throw ImageError(name, "environment map pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                               kChannel[i % 3] + " is " + (std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "negative") +
                               " (radiance must be finite and >= 0)");
  }
}

// Sampling weights: luminance times sin(theta) at the row's centre, the Jacobian of the
// (u, v) -> sphere map, so bright pixels near the poles are not oversampled.
std::vector<float> sampling_weights(const ImageRGB& image) {
  std::vector<float> w(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    const auto sin_theta = static_cast<float>(std::sin(kPi * (y + 0.5) / image.height));
    for (int x = 0; x < image.width; ++x)
      w[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)] =
          luminance(image.at(x, y)) * sin_theta;
  }
  return w;
}

struct Pixel {
  std::size_t x, y;
};

Pixel pixel_of(const glm::dvec2& uv, int width, int height) {
  const auto w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  return {std::min(static_cast<std::size_t>(uv.x * static_cast<double>(w)), w - 1),
          std::min(static_cast<std::size_t>(uv.y * static_cast<double>(h)), h - 1)};
}

}  // namespace

glm::vec3 equirect_direction(double u, double v) {
  const double phi = 2.0 * kPi * (u - 0.5), theta = kPi * v;
  const double s = std::sin(theta);
  return {static_cast<float>(s * std::sin(phi)), static_cast<float>(std::cos(theta)),
          static_cast<float>(-s * std::cos(phi))};
}

glm::dvec2 equirect_uv(const glm::vec3& dir) {
  const double x = dir.x, y = dir.y, z = dir.z;
  const double phi = std::atan2(x, -z);
  const double theta = std::atan2(std::sqrt(x * x + z * z), y);
  return {std::clamp(0.5 + phi / (2.0 * kPi), 0.0, 1.0), std::clamp(theta / kPi, 0.0, 1.0)};
}

Environment::Environment(const glm::vec3& radiance) : constant_(radiance) {
  if (!finite_non_negative(radiance.x) || !finite_non_negative(radiance.y) || !finite_non_negative(radiance.z))
    throw std::invalid_argument("environment colour must be finite and >= 0");
}

Environment::Environment(const std::filesystem::path& file, float scale)
    : Environment(read_image(file), scale, file.string()) {}

Environment::Environment(ImageRGB image, float scale, const std::string& name) : image_(std::move(image)) {
  if (!finite_non_negative(scale)) throw ImageError(name, "environment scale must be finite and >= 0");
  check_pixels(image_, name);
  const std::vector<float> weights = sampling_weights(image_);
  distribution_.emplace(weights, static_cast<std::size_t>(image_.width), static_cast<std::size_t>(image_.height));
  for (float& v : image_.rgb) v *= scale;
  for (float v : image_.rgb)
    if (!std::isfinite(v)) throw ImageError(name, "environment scale makes the radiance overflow");
}

glm::vec3 Environment::radiance(const glm::vec3& dir) const {
  if (is_constant()) return constant_;
  const Pixel p = pixel_of(equirect_uv(dir), image_.width, image_.height);
  return image_.at(static_cast<int>(p.x), static_cast<int>(p.y));
}

float Environment::pdf(const glm::vec3& dir) const {
  if (is_constant()) return static_cast<float>(1.0 / (4.0 * kPi));
  const double x = dir.x, y = dir.y, z = dir.z;
  const double len = std::sqrt(x * x + y * y + z * z);
  const double sin_theta = std::sqrt(x * x + z * z) / len;
  if (!(sin_theta > 0.0)) return 0.0f;  // the poles: a (u, v) density has no solid-angle density there
  const Pixel p = pixel_of(equirect_uv(dir), image_.width, image_.height);
  return static_cast<float>(distribution_->pdf(p.x, p.y) / (2.0 * kPi * kPi * sin_theta));
}

EnvSample Environment::sample(glm::vec2 u) const {
  EnvSample s;
  if (is_constant()) {
    // Uniform on the sphere: y uniform in (-1, 1], phi uniform (Archimedes).
    const double y = 1.0 - 2.0 * u.y, r = std::sqrt(std::max(0.0, 1.0 - y * y)), phi = 2.0 * kPi * u.x;
    s.dir = {static_cast<float>(r * std::sin(phi)), static_cast<float>(y), static_cast<float>(-r * std::cos(phi))};
    s.radiance = constant_;
    s.pdf = static_cast<float>(1.0 / (4.0 * kPi));
    return s;
  }
  const Distribution2D::Sample uv = distribution_->sample(u);
  s.dir = equirect_direction(uv.p.x, uv.p.y);
  // Radiance and density are both read back at the returned (rounded) direction, so on a
  // pixel edge they come from the same pixel and MIS sees exactly pdf(dir).
  s.radiance = radiance(s.dir);
  s.pdf = pdf(s.dir);
  return s;
}

}  // namespace lancer
