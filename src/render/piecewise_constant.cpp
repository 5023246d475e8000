#include "render/piecewise_constant.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lancer {

namespace {
constexpr float kOneMinusUlp = 1.0f - 0x1p-24f;  // the largest float below 1
}  // namespace

Distribution1D::Distribution1D(std::span<const float> weights) : cdf_(weights.size() + 1, 0.0f) {
  if (weights.empty()) throw std::invalid_argument("piecewise-constant distribution: no weights");
  double total = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!(weights[i] >= 0.0f) || !std::isfinite(weights[i]))
      throw std::invalid_argument("piecewise-constant distribution: weight " + std::to_string(i) +
                                  " is negative or not finite");
    total += weights[i];
  }
  const double n = static_cast<double>(weights.size());
  mean_ = total / n;
  double running = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    running += total > 0.0 ? static_cast<double>(weights[i]) : 1.0;
    cdf_[i + 1] = static_cast<float>(running / (total > 0.0 ? total : n));
  }
  cdf_.back() = 1.0f;
}

Distribution1D::Sample Distribution1D::sample(float u) const {
  u = std::clamp(u, 0.0f, kOneMinusUlp);
  // The last entry <= u: cdf_[0] = 0 <= u < 1 = cdf_.back(), and cdf_[bin] <= u <
  // cdf_[bin + 1] makes the chosen bin's probability positive.
  const auto above = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const auto bin = static_cast<std::size_t>(above - cdf_.begin()) - 1;
  const double lo = cdf_[bin], width = static_cast<double>(cdf_[bin + 1]) - lo;
  const double t = std::min((static_cast<double>(u) - lo) / width, 1.0);
  Sample s;
  s.bin = bin;
  s.x = std::min(static_cast<float>((static_cast<double>(bin) + t) / static_cast<double>(size())), kOneMinusUlp);
  s.pdf = static_cast<float>(width * static_cast<double>(size()));
  return s;
}

float Distribution1D::pdf(std::size_t bin) const {
  if (bin >= size()) return 0.0f;
  return static_cast<float>((static_cast<double>(cdf_[bin + 1]) - cdf_[bin]) * static_cast<double>(size()));
}

namespace {
Distribution1D row_marginal(const std::vector<Distribution1D>& rows) {
  std::vector<float> weights(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) weights[r] = static_cast<float>(rows[r].mean_weight());
  return Distribution1D(weights);
}

std::vector<Distribution1D> row_conditionals(std::span<const float> weights, std::size_t width, std::size_t height) {
  if (width == 0 || height == 0 || weights.size() / width != height || weights.size() % width != 0)
    throw std::invalid_argument("piecewise-constant 2D distribution: " + std::to_string(weights.size()) +
                                " weights for a " + std::to_string(width) + " x " + std::to_string(height) + " grid");
  std::vector<Distribution1D> rows;
  rows.reserve(height);
  for (std::size_t r = 0; r < height; ++r) rows.emplace_back(weights.subspan(r * width, width));
  return rows;
}
}  // namespace

Distribution2D::Distribution2D(std::span<const float> weights, std::size_t width, std::size_t height)
    : conditional_(row_conditionals(weights, width, height)), marginal_(row_marginal(conditional_)) {}

Distribution2D::Sample Distribution2D::sample(glm::vec2 u) const {
  const Distribution1D::Sample row = marginal_.sample(u.y);
  const Distribution1D::Sample column = conditional_[row.bin].sample(u.x);
  Sample s;
  s.p = {column.x, row.x};
  s.column = column.bin;
  s.row = row.bin;
  s.pdf = row.pdf * column.pdf;
  return s;
}

float Distribution2D::pdf(std::size_t column, std::size_t row) const {
  if (row >= height()) return 0.0f;
  return marginal_.pdf(row) * conditional_[row].pdf(column);
}

}  // namespace lancer
