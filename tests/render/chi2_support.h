// Chi-square goodness-of-fit testing of direction samplers, the way pbrt-v4 and Mitsuba test
// their BSDFs: bin the sphere in (cos theta, phi), integrate the claimed pdf over each bin by
// adaptive quadrature, histogram many samples, pool bins with small expected counts, and
// turn Pearson's statistic into a p-value with the regularised incomplete gamma function.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace lancer::test {

// ---- Regularised incomplete gamma function ---------------------------------------------

// Q(a, x) = Gamma(a, x) / Gamma(a), the upper regularised incomplete gamma function, for
// a > 0, x >= 0. Below x = a + 1 it sums the series of P = 1 - Q (the terms x^n / (a+1)...(a+n)),
// above it evaluates Legendre's continued fraction for Q with the modified Lentz method;
// each converges fast on its side (Abramowitz & Stegun 6.5.29 and 6.5.31).
inline double regularized_gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double log_prefactor = -x + a * std::log(x);  // log(e^-x x^a)
  constexpr double kEps = 1e-15;
  constexpr int kMaxTerms = 100000;
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < kMaxTerms; ++n) {
      term *= x / (a + n);
      sum += term;
      if (term < sum * kEps) break;
    }
    return std::max(0.0, 1.0 - std::exp(log_prefactor - std::lgamma(a)) * sum);
  }
  // Q = e^-x x^a / Gamma(a) * 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - 2 (2 - a) / (x + 5 - a - ...)))
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny, d = 1.0 / b, fraction = d;
  for (int n = 1; n < kMaxTerms; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    fraction *= step;
    if (std::abs(step - 1.0) < kEps) break;
  }
  return std::exp(log_prefactor - std::lgamma(a)) * fraction;
}

// Probability that a chi-square variable with `dof` degrees of freedom exceeds `statistic`.
inline double chi2_survival(double statistic, int dof) { return regularized_gamma_q(0.5 * dof, 0.5 * statistic); }

// Per-test significance that keeps the family-wise rate at `alpha` over `tests` tests (Sidak).
inline double sidak_significance(double alpha, int tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / tests); }

// ---- Adaptive quadrature ---------------------------------------------------------------

// What an adaptive integration did. Nested integrals (integrate_bins) share one report, so
// one budget bounds the whole job: the recursion below is a binary tree per level, and two
// nested levels that both fail to converge cost up to (2^(max_depth+1))^2 evaluations, a
// hang in practice. That happens whenever the integrand is NaN (every comparison with NaN
// is false, so no segment ever converges) or is noise-dominated above the relative
// tolerance over a whole interval. Both are now caught: a non-finite value stops the
// integration at once, and the budget ends it with `exhausted` set; either way the caller
// must fail rather than use the numbers.
struct QuadratureReport {
  long long evaluations = 0;
  long long budget = 20'000'000;  // evaluations allowed in total
  long long unresolved = 0;       // segments accepted unconverged (depth limit or budget)
  bool finite = true;             // false: the integrand returned NaN or infinity
  bool exhausted = false;         // the budget ran out before every segment converged
  bool ok() const { return finite && !exhausted; }
};

namespace detail {
// One Simpson step on [a, b] with midpoint m; `error` accumulates the Richardson error
// estimate |delta| / 15 of converged segments and the whole |delta| of unconverged ones.
template <class F>
double simpson_step(F& f, double a, double fa, double b, double fb, double m, double fm, double whole, double tol,
                    double rel_tol, int depth, QuadratureReport& report, double& error) {
  if (!report.finite) return std::numeric_limits<double>::quiet_NaN();
  if (report.evaluations >= report.budget) {
    report.exhausted = true;
    ++report.unresolved;
    return whole;
  }
  const double lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  report.evaluations += 2;
  if (!std::isfinite(flm) || !std::isfinite(frm)) {
    report.finite = false;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  const double delta = left + right - whole;
  const bool converged = std::abs(delta) <= 15.0 * std::max(tol, rel_tol * std::abs(left + right));
  if (converged || depth <= 0) {
    error += converged ? std::abs(delta) / 15.0 : std::abs(delta);
    if (!converged) ++report.unresolved;
    return left + right + delta / 15.0;
  }
  return simpson_step(f, a, fa, m, fm, lm, flm, left, 0.5 * tol, rel_tol, depth - 1, report, error) +
         simpson_step(f, m, fm, b, fb, rm, frm, right, 0.5 * tol, rel_tol, depth - 1, report, error);
}
}  // namespace detail

// Integral of f over [a, b] by adaptive Simpson (Richardson-corrected), refining until the
// error estimate is below `tol` absolute or `rel_tol` relative, at most max_depth halvings
// deep. The relative bound keeps the recursion above the rounding noise of a float
// integrand, which no absolute tolerance below 1e-7 of the peak value could ever meet.
// Adds the estimated absolute error to `error` and the work done to `report`; returns NaN
// once the integrand was not finite.
template <class F>
double adaptive_simpson(F&& f, double a, double b, double tol, double rel_tol, int max_depth,
                        QuadratureReport& report, double& error) {
  if (!report.finite) return std::numeric_limits<double>::quiet_NaN();
  if (report.evaluations >= report.budget) {
    report.exhausted = true;
    ++report.unresolved;
    return 0.0;
  }
  const double m = 0.5 * (a + b);
  const double fa = f(a), fb = f(b), fm = f(m);
  report.evaluations += 3;
  if (!std::isfinite(fa) || !std::isfinite(fb) || !std::isfinite(fm)) {
    report.finite = false;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
  return detail::simpson_step(f, a, fa, b, fb, m, fm, whole, tol, rel_tol, max_depth, report, error);
}

// The same for a single integral that must succeed: throws std::runtime_error (a test
// failure that names the cause) on a non-finite integrand or an exhausted budget.
template <class F>
double adaptive_simpson(F&& f, double a, double b, double tol, double rel_tol = 1e-6, int max_depth = 16) {
  QuadratureReport report;
  double error = 0.0;
  const double v = adaptive_simpson(f, a, b, tol, rel_tol, max_depth, report, error);
  if (!report.finite) throw std::runtime_error("adaptive_simpson: the integrand is not finite");
  if (report.exhausted) throw std::runtime_error("adaptive_simpson: evaluation budget exhausted");
  return v;
}

// ---- Sphere bins -----------------------------------------------------------------------

// Bins over the sphere of local directions: n_cos equal slices of cos(theta) in [-1, 1]
// times n_phi equal slices of phi in [0, 2 pi). Equal slices of cos theta have equal area.
struct SphereBins {
  int n_cos = 10;
  int n_phi = 20;

  int size() const { return n_cos * n_phi; }
  // The bin of unit direction d, or -1 when d is not finite (a NaN would otherwise turn
  // into INT_MIN through the int conversion and index far outside the histogram).
  int index(const glm::vec3& d) const {
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return -1;
    const double c = std::clamp(static_cast<double>(d.z), -1.0, 1.0);
    double phi = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x));
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    const int ic = std::min(n_cos - 1, static_cast<int>((c + 1.0) * 0.5 * n_cos));
    const int ip = std::min(n_phi - 1, static_cast<int>(phi / (2.0 * std::numbers::pi) * n_phi));
    return ic * n_phi + ip;
  }
};

// Per-bin integrals of a density over the sphere, with their estimated absolute errors.
struct BinIntegrals {
  std::vector<double> value, error;
  QuadratureReport report;
  glm::vec3 non_finite_at{0.0f};  // a direction where the density was not finite (when !report.finite)

  // Empty when the numbers can be used; else what went wrong.
  std::string problem() const {
    std::ostringstream m;
    if (!report.finite)
      m << "density not finite at (" << non_finite_at.x << ", " << non_finite_at.y << ", " << non_finite_at.z << ")";
    else if (report.exhausted)
      m << "quadrature budget of " << report.budget << " evaluations exhausted (" << report.unresolved
        << " segments unconverged)";
    return m.str();
  }
};

// The integral of density(direction) over each bin, each to about `tol`. The outer
// integral runs over theta (dw = sin(theta) dtheta dphi) rather than cos(theta): a lobe
// at a pole is ~alpha wide in theta but ~alpha^2 in cos(theta). Sharp peaks defeat adaptive
// quadrature when no node lands near them, so each bin is first cut at the theta and phi of
// every direction in `peaks` (the mirror and refraction directions of a glossy lobe).
// A bin's error is the outer integral's own estimate plus the largest inner (phi) error
// times the theta range, a bound on the integral of the inner errors.
template <class Density>
BinIntegrals integrate_bins_checked(Density&& density, const SphereBins& bins, const std::vector<glm::vec3>& peaks,
                                    double tol, long long budget = 20'000'000) {
  const double dc = 2.0 / bins.n_cos, dphi = 2.0 * std::numbers::pi / bins.n_phi;
  std::vector<double> peak_theta, peak_phi;
  for (const glm::vec3& p : peaks) {
    peak_theta.push_back(std::acos(std::clamp(static_cast<double>(p.z), -1.0, 1.0)));
    double phi = std::atan2(static_cast<double>(p.y), static_cast<double>(p.x));
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    peak_phi.push_back(phi);
  }
  const auto cuts = [](double lo, double hi, const std::vector<double>& at) {
    std::vector<double> c{lo, hi};
    for (double x : at)
      if (x > lo && x < hi) c.push_back(x);
    std::sort(c.begin(), c.end());
    return c;
  };
  BinIntegrals out;
  out.value.assign(bins.size(), 0.0);
  out.error.assign(bins.size(), 0.0);
  QuadratureReport& report = out.report;
  report.budget = budget;
  for (int ic = 0; ic < bins.n_cos && report.ok(); ++ic) {
    // theta decreases as cos(theta) increases.
    const double theta_lo = std::acos(std::min(1.0, -1.0 + (ic + 1) * dc));
    const double theta_hi = std::acos(std::max(-1.0, -1.0 + ic * dc));
    const std::vector<double> tc = cuts(theta_lo, theta_hi, peak_theta);
    for (int ip = 0; ip < bins.n_phi && report.ok(); ++ip) {
      const std::vector<double> pc = cuts(ip * dphi, (ip + 1) * dphi, peak_phi);
      double sum = 0.0, outer_error = 0.0;
      for (size_t i = 0; i + 1 < tc.size(); ++i) {
        const double t0 = tc[i], t1 = tc[i + 1];
        double worst_inner = 0.0;  // largest phi-integration error seen, times sin(theta)
        const auto inner = [&](double theta) {
          const double sin_theta = std::sin(theta), cos_theta = std::cos(theta);
          double s = 0.0, inner_error = 0.0;
          for (size_t j = 0; j + 1 < pc.size(); ++j) {
            const auto f = [&](double phi) {
              const glm::vec3 d(static_cast<float>(sin_theta * std::cos(phi)),
                                static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(cos_theta));
              const double v = static_cast<double>(density(d));
              if (!std::isfinite(v) && report.finite) out.non_finite_at = d;
              return v;
            };
            s += adaptive_simpson(f, pc[j], pc[j + 1], 0.1 * tol / (t1 - t0) / (pc.size() - 1), 1e-6, 16, report,
                                  inner_error);
          }
          worst_inner = std::max(worst_inner, inner_error * sin_theta);
          return s * sin_theta;
        };
        sum += adaptive_simpson(inner, t0, t1, 0.5 * tol / (tc.size() - 1), 1e-5, 16, report, outer_error);
        outer_error += worst_inner * (t1 - t0);
      }
      out.value[ic * bins.n_phi + ip] = sum;
      out.error[ic * bins.n_phi + ip] = outer_error;
    }
  }
  return out;
}

// The per-bin integrals alone; throws std::runtime_error (a test failure naming the cause)
// when the quadrature could not produce them.
template <class Density>
std::vector<double> integrate_bins(Density&& density, const SphereBins& bins, const std::vector<glm::vec3>& peaks,
                                   double tol) {
  BinIntegrals r = integrate_bins_checked(density, bins, peaks, tol);
  if (const std::string p = r.problem(); !p.empty()) throw std::runtime_error("integrate_bins: " + p);
  return std::move(r.value);
}

// ---- Pearson's test with pooling -------------------------------------------------------

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 1.0;
  std::string message;  // empty when the histogram is consistent with the expectation
};

// Compares observed counts with expected counts cell by cell. Cells expecting fewer than
// `min_expected` are pooled into one (with the next smallest cells added until the pool
// reaches min_expected), as the chi-square approximation needs. A cell with observations
// but (numerically) no expectation fails outright: the sampler produced an impossible value.
inline Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                            double significance, double min_expected = 5.0) {
  Chi2Result r;
  const double total = std::accumulate(expected.begin(), expected.end(), 0.0);
  std::vector<size_t> order(expected.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pool_obs = 0.0, pool_exp = 0.0;
  int cells = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    const size_t i = order[k];
    if (expected[i] < 1e-12 * total && observed[i] > 0.0) {
      std::ostringstream m;
      m << "cell " << i << " has " << observed[i] << " samples but expects " << expected[i];
      r.message = m.str();
      return r;
    }
    if (expected[i] < min_expected || pool_exp < min_expected) {
      pool_obs += observed[i];
      pool_exp += expected[i];
      continue;
    }
    r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pool_exp > 0.0) {
    r.statistic += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
    ++cells;
  }
  r.dof = cells - 1;
  if (r.dof < 1) {
    r.message = "fewer than two cells after pooling";
    return r;
  }
  r.p_value = chi2_survival(r.statistic, r.dof);
  if (r.p_value < significance) {
    std::ostringstream m;
    m << "chi-square " << r.statistic << " with " << r.dof << " dof: p = " << r.p_value << " < " << significance;
    r.message = m.str();
  }
  return r;
}

}  // namespace lancer::test
