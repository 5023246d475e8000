// Float arithmetic, fused multiply-add, comparisons, select and reductions at every width,
// against the scalar type lane by lane, plus the NaN and signed-zero rules stated in
// src/simd/vfloat4_sse4.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "vector_ops_fixture.h"

namespace lancer::test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

class VFloatTest : public VectorOpsTest {};

std::vector<float> unary(const VectorOpsTable& t, FloatUnary op, const std::vector<float>& a) {
  std::vector<float> out(a.size());
  t.float_unary(op, a.data(), out.data(), static_cast<int>(a.size()));
  return out;
}
std::vector<float> binary(const VectorOpsTable& t, FloatBinary op, const std::vector<float>& a,
                          const std::vector<float>& b) {
  std::vector<float> out(a.size());
  t.float_binary(op, a.data(), b.data(), out.data(), static_cast<int>(a.size()));
  return out;
}
std::vector<float> ternary(const VectorOpsTable& t, FloatTernary op, const std::vector<float>& a,
                           const std::vector<float>& b, const std::vector<float>& c) {
  std::vector<float> out(a.size());
  t.float_ternary(op, a.data(), b.data(), c.data(), out.data(), static_cast<int>(a.size()));
  return out;
}
std::vector<std::int32_t> compare(const VectorOpsTable& t, Compare op, const std::vector<float>& a,
                                  const std::vector<float>& b) {
  std::vector<std::int32_t> out(a.size());
  t.float_compare(op, a.data(), b.data(), out.data(), static_cast<int>(a.size()));
  return out;
}
std::vector<std::uint32_t> bits(const std::vector<float>& v) {
  std::vector<std::uint32_t> out;
  for (float x : v) out.push_back(std::bit_cast<std::uint32_t>(x));
  return out;
}
// Repeats `pattern` to kLanes lanes, so every entry lands on every lane position.
std::vector<float> cycle(const std::vector<float>& pattern) {
  std::vector<float> out(kLanes);
  for (int i = 0; i < kLanes; ++i) out[i] = pattern[i % pattern.size()];
  return out;
}

TEST_P(VFloatTest, WidthAndBroadcast) {
  const int expected_width[] = {1, 4, 8, 16};
  EXPECT_EQ(width(), expected_width[static_cast<int>(isa())]);
  std::vector<float> f(width());
  std::vector<std::int32_t> i(width()), b(width());
  ops().broadcast(3.25f, -7, true, f.data(), i.data(), b.data());
  for (int k = 0; k < width(); ++k) {
    EXPECT_EQ(f[k], 3.25f) << "lane " << k;
    EXPECT_EQ(i[k], -7) << "lane " << k;
    EXPECT_EQ(b[k], 1) << "lane " << k;
  }
  ops().broadcast(-0.0f, 0, false, f.data(), i.data(), b.data());
  for (int k = 0; k < width(); ++k) {
    EXPECT_TRUE(std::signbit(f[k]) && f[k] == 0.0f) << "lane " << k;
    EXPECT_EQ(b[k], 0) << "lane " << k;
  }
}

TEST_P(VFloatTest, LaneAccessReadsLanesInMemoryOrder) {
  std::vector<float> f(width()), out_f(width());
  std::vector<std::int32_t> i(width()), m(width()), out_i(width()), out_m(width());
  for (int k = 0; k < width(); ++k) {
    f[k] = 0.5f + static_cast<float>(k);
    i[k] = 100 - k;
    m[k] = (k % 3 == 0) ? 1 : 0;
  }
  ops().lane_access(f.data(), i.data(), m.data(), out_f.data(), out_i.data(), out_m.data());
  EXPECT_EQ(out_f, f);
  EXPECT_EQ(out_i, i);
  EXPECT_EQ(out_m, m);
}

TEST_P(VFloatTest, ArithmeticMatchesScalar) {
  const auto a = floats_with_specials(kLanes, 1), b = floats_with_specials(kLanes, 2);
  for (FloatBinary op : {FloatBinary::Add, FloatBinary::Sub, FloatBinary::Mul, FloatBinary::Div}) {
    SCOPED_TRACE(static_cast<int>(op));
    EXPECT_TRUE(floats_match(binary(ops(), op, a, b), binary(scalar(), op, a, b), "binary op"));
  }
  // Cross-check the scalar reference itself on a few lanes.
  const auto sum = binary(scalar(), FloatBinary::Add, a, b);
  for (int k = 1; k < 40; k += 3) EXPECT_TRUE(same_float(sum[k], a[k] + b[k])) << k;
}

TEST_P(VFloatTest, NegAbsSqrtMatchScalar) {
  const auto a = floats_with_specials(kLanes, 3);
  // Neg and abs only touch the sign bit, NaN included: compare every bit.
  EXPECT_TRUE(ints_match(bits(unary(ops(), FloatUnary::Neg, a)), bits(unary(scalar(), FloatUnary::Neg, a)), "neg"));
  EXPECT_TRUE(ints_match(bits(unary(ops(), FloatUnary::Abs, a)), bits(unary(scalar(), FloatUnary::Abs, a)), "abs"));
  const auto abs_a = unary(ops(), FloatUnary::Abs, a);
  for (int k = 0; k < kLanes; ++k) EXPECT_FALSE(std::signbit(abs_a[k])) << k;
  EXPECT_TRUE(floats_match(unary(ops(), FloatUnary::Sqrt, a), unary(scalar(), FloatUnary::Sqrt, a), "sqrt"));
}

TEST_P(VFloatTest, MinMaxMatchScalar) {
  const auto a = floats_with_specials(kLanes, 4), b = floats_with_specials(kLanes, 5);
  EXPECT_TRUE(floats_match(binary(ops(), FloatBinary::Min, a, b), binary(scalar(), FloatBinary::Min, a, b), "min"));
  EXPECT_TRUE(floats_match(binary(ops(), FloatBinary::Max, a, b), binary(scalar(), FloatBinary::Max, a, b), "max"));
}

// min/max follow minps/maxps: when either operand is NaN, or both are zeros, the result
// is the second operand.
TEST_P(VFloatTest, MinMaxWithNaNOrZerosReturnSecondOperand) {
  const auto a = cycle({kNaN, 1.0f, kNaN, -0.0f, 0.0f, 1.0f, -kInf, kInf});
  const auto b = cycle({1.0f, kNaN, kNaN, 0.0f, -0.0f, 2.0f, kInf, kNaN});
  const auto want_min = cycle({1.0f, kNaN, kNaN, 0.0f, -0.0f, 1.0f, -kInf, kNaN});
  const auto want_max = cycle({1.0f, kNaN, kNaN, 0.0f, -0.0f, 2.0f, kInf, kNaN});
  EXPECT_TRUE(floats_match(binary(ops(), FloatBinary::Min, a, b), want_min, "min"));
  EXPECT_TRUE(floats_match(binary(ops(), FloatBinary::Max, a, b), want_max, "max"));
}

// AVX2, AVX-512 and scalar round once (std::fma); SSE4 has no FMA and rounds a*b first.
TEST_P(VFloatTest, FusedMultiplyAdd) {
  const auto a = random_floats(kLanes, 6, -4.0f, 4.0f), b = random_floats(kLanes, 7, -4.0f, 4.0f);
  const auto c = random_floats(kLanes, 8, -16.0f, 16.0f);
  std::vector<float> madd(kLanes), msub(kLanes), nmadd(kLanes);
  for (int k = 0; k < kLanes; ++k) {
    if (has_fma()) {
      madd[k] = std::fma(a[k], b[k], c[k]);
      msub[k] = std::fma(a[k], b[k], -c[k]);
      nmadd[k] = std::fma(-a[k], b[k], c[k]);
    } else {
      const float ab = a[k] * b[k];  // generic code is built with -ffp-contract=off
      madd[k] = ab + c[k];
      msub[k] = ab - c[k];
      nmadd[k] = c[k] - ab;
    }
  }
  EXPECT_TRUE(floats_match(ternary(ops(), FloatTernary::Fmadd, a, b, c), madd, "fmadd"));
  EXPECT_TRUE(floats_match(ternary(ops(), FloatTernary::Fmsub, a, b, c), msub, "fmsub"));
  EXPECT_TRUE(floats_match(ternary(ops(), FloatTernary::Fnmadd, a, b, c), nmadd, "fnmadd"));

  // (1 + 2^-12)^2 = 1 + 2^-11 + 2^-24 exactly; rounded to float it is 1 + 2^-11. A single
  // rounding keeps the 2^-24 in fmsub, two roundings lose it.
  const float x = 1.0f + std::ldexp(1.0f, -12);
  const auto one_rounding = ternary(ops(), FloatTernary::Fmsub, cycle({x}), cycle({x}), cycle({1.0f + std::ldexp(1.0f, -11)}));
  for (int k = 0; k < width(); ++k) EXPECT_EQ(one_rounding[k], has_fma() ? std::ldexp(1.0f, -24) : 0.0f) << k;
}

TEST_P(VFloatTest, ComparisonsMatchScalar) {
  auto a = floats_with_specials(kLanes, 9), b = floats_with_specials(kLanes, 10);
  for (int k = 0; k < kLanes; k += 5) b[k] = a[k];  // equal lanes too
  for (Compare op : {Compare::Lt, Compare::Le, Compare::Gt, Compare::Ge, Compare::Eq, Compare::Ne}) {
    SCOPED_TRACE(static_cast<int>(op));
    EXPECT_TRUE(ints_match(compare(ops(), op, a, b), compare(scalar(), op, a, b), "compare"));
  }
}

// Comparisons are ordered: false whenever an operand is NaN, except != (true). -0 == +0.
TEST_P(VFloatTest, ComparisonsWithNaNAreFalseExceptNotEqual) {
  const auto a = cycle({kNaN, 1.0f, kNaN, kInf, -0.0f});
  const auto b = cycle({1.0f, kNaN, kNaN, kNaN, 0.0f});
  const std::vector<std::pair<Compare, std::vector<float>>> cases = {
      {Compare::Lt, {0, 0, 0, 0, 0}}, {Compare::Le, {0, 0, 0, 0, 1}}, {Compare::Gt, {0, 0, 0, 0, 0}},
      {Compare::Ge, {0, 0, 0, 0, 1}}, {Compare::Eq, {0, 0, 0, 0, 1}}, {Compare::Ne, {1, 1, 1, 1, 0}}};
  for (const auto& [op, pattern] : cases) {
    const auto got = compare(ops(), op, a, b);
    const auto want = cycle(pattern);
    for (int k = 0; k < kLanes; ++k)
      ASSERT_EQ(got[k], static_cast<std::int32_t>(want[k])) << "op " << static_cast<int>(op) << " lane " << k;
  }
}

TEST_P(VFloatTest, SelectTakesFirstOperandWhereMaskIsSet) {
  const auto m = random_mask(kLanes, 11);
  const auto a = floats_with_specials(kLanes, 12), b = floats_with_specials(kLanes, 13);
  std::vector<float> got(kLanes), want(kLanes);
  ops().select_float(m.data(), a.data(), b.data(), got.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) want[k] = m[k] ? a[k] : b[k];
  EXPECT_TRUE(ints_match(bits(got), bits(want), "select"));
}

TEST_P(VFloatTest, ReductionsOfIntegerValuesAreExact) {
  std::vector<float> a;
  for (std::int32_t x : random_ints(kLanes, 14, -1000, 1000)) a.push_back(static_cast<float>(x));
  const int n = kLanes / width();
  std::vector<float> mn(n), mx(n), add(n);
  ops().float_reductions(a.data(), mn.data(), mx.data(), add.data(), kLanes);
  for (int v = 0; v < n; ++v) {
    float want_min = a[v * width()], want_max = want_min, want_add = 0.0f;
    for (int k = v * width(); k < (v + 1) * width(); ++k) {
      want_min = std::min(want_min, a[k]);
      want_max = std::max(want_max, a[k]);
      want_add += a[k];
    }
    ASSERT_EQ(mn[v], want_min) << "vector " << v;
    ASSERT_EQ(mx[v], want_max) << "vector " << v;
    ASSERT_EQ(add[v], want_add) << "vector " << v;
  }
}

// reduce_add sums pairwise: each partial sum rounds once, so the error is at most
// (log2(width)) * 2^-24 * sum|x|, well inside width * 2^-24 * sum|x|.
TEST_P(VFloatTest, ReduceAddOfRandomValuesIsWithinRoundingBound) {
  const auto a = random_floats(kLanes, 15, -1000.0f, 1000.0f);
  const int n = kLanes / width();
  std::vector<float> mn(n), mx(n), add(n);
  ops().float_reductions(a.data(), mn.data(), mx.data(), add.data(), kLanes);
  for (int v = 0; v < n; ++v) {
    double exact = 0.0, magnitude = 0.0;
    for (int k = v * width(); k < (v + 1) * width(); ++k) {
      exact += a[k];
      magnitude += std::fabs(a[k]);
    }
    EXPECT_LE(std::fabs(add[v] - exact), width() * std::ldexp(1.0, -24) * magnitude) << "vector " << v;
  }
}

// The sign test of a watertight ray/triangle intersection over `width` triangles.
TEST_P(VFloatTest, WatertightEdgeTestMatchesScalar) {
  std::vector<std::vector<float>> xy;
  for (std::uint32_t c = 0; c < 6; ++c) {
    auto coords = random_floats(kLanes, 20 + c, -2.0f, 2.0f);
    // Small integers put many rays exactly on edges and vertices (U, V or W == 0).
    for (int k = 0; k < kLanes; k += 2) coords[k] = std::round(coords[k]);
    xy.push_back(coords);
  }
  const float* ptrs[6] = {xy[0].data(), xy[1].data(), xy[2].data(), xy[3].data(), xy[4].data(), xy[5].data()};
  std::vector<std::int32_t> hit(kLanes), want_hit(kLanes);
  std::vector<float> det(kLanes), want_det(kLanes);
  ops().edge_test(ptrs, hit.data(), det.data(), kLanes);
  scalar().edge_test(ptrs, want_hit.data(), want_det.data(), kLanes);
  EXPECT_TRUE(ints_match(hit, want_hit, "hit"));
  EXPECT_TRUE(floats_match(det, want_det, "det"));
  int hits = 0;
  for (int h : hit) hits += h;
  EXPECT_GT(hits, kLanes / 20);  // both outcomes occur, so the comparison means something
  EXPECT_LT(hits, kLanes - kLanes / 20);

  // A triangle around the origin is hit in either winding; one beside it is missed.
  std::vector<std::vector<float>> tri = {{-1, -1}, {-1, -1}, {1, 0}, {-1, 1}, {0, 1}, {1, -1}};
  std::vector<std::vector<float>> lanes(6);
  for (int c = 0; c < 6; ++c) lanes[c] = cycle(tri[c]);  // lane 2k: ccw, lane 2k+1: cw
  for (int k = 0; k < kLanes; k += 4)
    for (int c = 0; c < 6; c += 2) lanes[c][k] += 5.0f;  // shift x: no longer around the origin
  const float* tri_ptrs[6] = {lanes[0].data(), lanes[1].data(), lanes[2].data(),
                              lanes[3].data(), lanes[4].data(), lanes[5].data()};
  ops().edge_test(tri_ptrs, hit.data(), det.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) EXPECT_EQ(hit[k], k % 4 == 0 ? 0 : 1) << "lane " << k;
}

INSTANTIATE_TEST_SUITE_P(AllIsas, VFloatTest, ::testing::ValuesIn(all_isas()), isa_param_name);

}  // namespace
}  // namespace lancer::test
