// rcp and rsqrt (hardware estimate + one Newton-Raphson step) at every width: the maximum
// relative error over every mantissa, and the exact special values.
#include <cmath>
#include <bit>
#include <cstdint>
#include <iostream>
#include <limits>
#include <vector>

#include "vector_ops_fixture.h"

namespace lancer::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

class VPrecisionTest : public VectorOpsTest {
 protected:
  // Max relative error of `op` against the double-precision reference over `inputs`.
  double max_rel_error(FloatUnary op, const std::vector<float>& inputs, float* worst_input) const {
    std::vector<float> out(inputs.size());
    ops().float_unary(op, inputs.data(), out.data(), static_cast<int>(inputs.size()));
    double worst = 0.0;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const double x = inputs[k];
      const double exact = op == FloatUnary::Rcp ? 1.0 / x : 1.0 / std::sqrt(x);
      const double err = std::fabs(out[k] - exact) / exact;
      if (!(err <= worst)) {  // also catches NaN
        worst = err;
        *worst_input = inputs[k];
      }
    }
    return worst;
  }

  // Every mantissa of [lo, lo * 2^binades), then random exponents across the normal range.
  void check_bound(FloatUnary op, float lo, int binades, float bound, const char* name) const {
    const std::uint32_t first = std::bit_cast<std::uint32_t>(lo);
    const std::uint32_t count = static_cast<std::uint32_t>(binades) << 23;
    double worst = 0.0;
    float worst_input = 0.0f;
    std::vector<float> chunk;
    for (std::uint32_t start = 0; start < count; start += 1u << 20) {
      chunk.clear();
      for (std::uint32_t k = start; k < start + (1u << 20) && k < count; ++k)
        chunk.push_back(std::bit_cast<float>(first + k));
      float input = 0.0f;
      const double err = max_rel_error(op, chunk, &input);
      if (err > worst) worst = err, worst_input = input;
    }
    // Exponents keep input and result normal: |x| in [2^-125, 2^125].
    const auto mantissas = random_floats(1 << 16, 77, 1.0f, 2.0f);
    const auto exponents = random_ints(1 << 16, 78, -125, 124);
    chunk.clear();
    for (std::size_t k = 0; k < mantissas.size(); ++k) chunk.push_back(std::ldexp(mantissas[k], exponents[k]));
    float input = 0.0f;
    const double err = max_rel_error(op, chunk, &input);
    if (err > worst) worst = err, worst_input = input;

    std::cout << "[ measured ] " << isa_name(isa()) << " " << name << " max relative error " << worst
              << " (bound " << bound << ")\n";
    EXPECT_LE(worst, bound) << name << " at x = " << worst_input;
  }
};

TEST_P(VPrecisionTest, RcpRelativeErrorWithinBound) {
  check_bound(FloatUnary::Rcp, 1.0f, 1, ops().rcp_max_rel_error, "rcp");
}

// Two binades: rsqrt's error pattern depends on the exponent's parity.
TEST_P(VPrecisionTest, RsqrtRelativeErrorWithinBound) {
  check_bound(FloatUnary::Rsqrt, 1.0f, 2, ops().rsqrt_max_rel_error, "rsqrt");
}

TEST_P(VPrecisionTest, RcpSpecialValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> in(kLanes), out(kLanes);
  const float inputs[] = {0.0f, -0.0f, kInf, -kInf, nan, -nan, kInf};
  const float expected[] = {kInf, -kInf, 0.0f, -0.0f, nan, nan, 0.0f};
  for (int k = 0; k < kLanes; ++k) in[k] = inputs[k % 7];
  ops().float_unary(FloatUnary::Rcp, in.data(), out.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) ASSERT_TRUE(same_float(out[k], expected[k % 7])) << "rcp(" << in[k] << ") = " << out[k];
}

TEST_P(VPrecisionTest, RsqrtSpecialValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> in(kLanes), out(kLanes);
  const float inputs[] = {0.0f, -0.0f, kInf, -1.0f, nan, -kInf, -0.5f};
  const float expected[] = {kInf, -kInf, 0.0f, nan, nan, nan, nan};
  for (int k = 0; k < kLanes; ++k) in[k] = inputs[k % 7];
  ops().float_unary(FloatUnary::Rsqrt, in.data(), out.data(), kLanes);
  for (int k = 0; k < kLanes; ++k)
    ASSERT_TRUE(same_float(out[k], expected[k % 7])) << "rsqrt(" << in[k] << ") = " << out[k];
}

INSTANTIATE_TEST_SUITE_P(AllIsas, VPrecisionTest, ::testing::ValuesIn(all_isas()), isa_param_name);

}  // namespace
}  // namespace lancer::test
