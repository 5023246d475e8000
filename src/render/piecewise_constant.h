// Piecewise-constant densities on [0, 1) and [0, 1)^2, sampled by inverting their CDFs
// (Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed., sections A.1 and A.5).
//
// Only the normalised CDF is stored (one float per bin, plus one). A bin's probability
// is defined as the difference of its two CDF entries, so the density reported by pdf()
// is exactly the density sample() draws from, rounding included. The CDF is summed in
// double and rounded once per entry, so it is non-decreasing and ends at exactly 1.
// Precision: a bin's probability is within 2^-24 (absolute) of weight / total, which is
// also the resolution of a 24-bit u; bins far below that are drawn with probability 0
// (and report pdf 0) or rounded up to one step.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

namespace lancer {

class Distribution1D {
 public:
  // weights: finite and >= 0 (std::invalid_argument otherwise), at least one. All zero
  // gives the uniform density.
  explicit Distribution1D(std::span<const float> weights);

  struct Sample {
    float x = 0.0f;       // in [0, 1)
    std::size_t bin = 0;  // floor(x * size()), the bin x lies in
    float pdf = 0.0f;     // density at x with respect to x in [0, 1)
  };
  // u in [0, 1). Bins of zero probability are never returned.
  Sample sample(float u) const;

  // Density of bin `bin` (with respect to x in [0, 1)): size() * P(bin).
  float pdf(std::size_t bin) const;
  std::size_t size() const { return cdf_.size() - 1; }
  // Sum of the weights divided by their count (0 when all are zero).
  double mean_weight() const { return mean_; }

 private:
  std::vector<float> cdf_;  // cdf_[0] = 0, cdf_[size()] = 1
  double mean_ = 0.0;
};

// A density over [0, 1)^2 on a width x height grid of cells (rows along y): the
// marginal picks a row by its total weight, then the row's conditional picks the column.
class Distribution2D {
 public:
  // weights row-major, width * height of them, same rules as Distribution1D.
  Distribution2D(std::span<const float> weights, std::size_t width, std::size_t height);

  struct Sample {
    glm::vec2 p{0.0f};  // in [0, 1)^2
    std::size_t column = 0, row = 0;
    float pdf = 0.0f;  // density with respect to area in [0, 1)^2
  };
  Sample sample(glm::vec2 u) const;
  float pdf(std::size_t column, std::size_t row) const;

  std::size_t width() const { return conditional_.empty() ? 0 : conditional_.front().size(); }
  std::size_t height() const { return conditional_.size(); }

 private:
  std::vector<Distribution1D> conditional_;  // one per row
  Distribution1D marginal_;
};

}  // namespace lancer
