// Int32 lanes at every width: arithmetic, logic, shifts, comparisons, select, reductions,
// and the conversions and bitcasts between int and float lanes.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "vector_ops_fixture.h"

namespace lancer::test {
namespace {

constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();

class VIntTest : public VectorOpsTest {};

using Ints = std::vector<std::int32_t>;

Ints int_binary(const VectorOpsTable& t, IntBinary op, const Ints& a, const Ints& b) {
  Ints out(a.size());
  t.int_binary(op, a.data(), b.data(), out.data(), static_cast<int>(a.size()));
  return out;
}
Ints int_unary(const VectorOpsTable& t, IntUnary op, const Ints& a, int shift) {
  Ints out(a.size());
  t.int_unary(op, a.data(), shift, out.data(), static_cast<int>(a.size()));
  return out;
}
Ints int_compare(const VectorOpsTable& t, Compare op, const Ints& a, const Ints& b) {
  Ints out(a.size());
  t.int_compare(op, a.data(), b.data(), out.data(), static_cast<int>(a.size()));
  return out;
}

// Values small enough that the scalar reference (plain C++ int) cannot overflow.
TEST_P(VIntTest, ArithmeticAndLogicMatchScalar) {
  const auto a = random_ints(kLanes, 1, -40000, 40000), b = random_ints(kLanes, 2, -40000, 40000);
  for (IntBinary op : {IntBinary::Add, IntBinary::Sub, IntBinary::Mul, IntBinary::And, IntBinary::Or, IntBinary::Xor,
                       IntBinary::Andnot, IntBinary::Min, IntBinary::Max}) {
    SCOPED_TRACE(static_cast<int>(op));
    EXPECT_TRUE(ints_match(int_binary(ops(), op, a, b), int_binary(scalar(), op, a, b), "int op"));
  }
  const auto andnot = int_binary(ops(), IntBinary::Andnot, a, b);
  const auto product = int_binary(ops(), IntBinary::Mul, a, b);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(andnot[k], a[k] & ~b[k]) << k;
    ASSERT_EQ(product[k], a[k] * b[k]) << k;
  }
  EXPECT_TRUE(ints_match(int_unary(ops(), IntUnary::Neg, a, 0), int_unary(scalar(), IntUnary::Neg, a, 0), "neg"));
}

// The vectors wrap on overflow (the scalar reference is not used here: C++ int overflow is UB).
TEST_P(VIntTest, VectorArithmeticWraps) {
  if (isa() == Isa::Scalar) GTEST_SKIP() << "width 1 uses plain C++ int arithmetic, where overflow is undefined";
  const Ints a(kLanes, kMax), one(kLanes, 1);
  const auto sum = int_binary(ops(), IntBinary::Add, a, one);
  for (int k = 0; k < kLanes; ++k) ASSERT_EQ(sum[k], kMin) << k;
}

TEST_P(VIntTest, ShiftsMatchScalar) {
  auto a = random_ints(kLanes, 3, kMin, kMax);
  a[0] = -8, a[1] = -1, a[2] = 1;
  for (int shift : {0, 1, 5, 17, 31}) {
    SCOPED_TRACE(shift);
    for (IntUnary op : {IntUnary::ShiftLeft, IntUnary::ShiftRightArithmetic, IntUnary::ShiftRightLogical})
      EXPECT_TRUE(ints_match(int_unary(ops(), op, a, shift), int_unary(scalar(), op, a, shift), "shift"));
  }
  const auto sra = int_unary(ops(), IntUnary::ShiftRightArithmetic, a, 1);
  const auto srl = int_unary(ops(), IntUnary::ShiftRightLogical, a, 28);
  const auto sll = int_unary(ops(), IntUnary::ShiftLeft, a, 31);
  EXPECT_EQ(sra[0], -4);
  EXPECT_EQ(sra[1], -1);
  EXPECT_EQ(srl[1], 15);
  EXPECT_EQ(sll[2], kMin);
}

// Signed comparisons, including the extremes.
TEST_P(VIntTest, ComparisonsMatchScalar) {
  auto a = random_ints(kLanes, 4, -5, 5), b = random_ints(kLanes, 5, -5, 5);
  for (int k = 0; k + 2 < kLanes; k += 7) a[k] = kMin, b[k + 1] = kMax, a[k + 2] = -1, b[k + 2] = 0;
  for (Compare op : {Compare::Lt, Compare::Le, Compare::Gt, Compare::Ge, Compare::Eq, Compare::Ne}) {
    SCOPED_TRACE(static_cast<int>(op));
    EXPECT_TRUE(ints_match(int_compare(ops(), op, a, b), int_compare(scalar(), op, a, b), "compare"));
  }
  const auto lt = int_compare(ops(), Compare::Lt, a, b);
  for (int k = 0; k < kLanes; ++k) ASSERT_EQ(lt[k], a[k] < b[k] ? 1 : 0) << k;
}

TEST_P(VIntTest, SelectTakesFirstOperandWhereMaskIsSet) {
  const auto m = random_mask(kLanes, 6);
  const auto a = random_ints(kLanes, 7, kMin, kMax), b = random_ints(kLanes, 8, kMin, kMax);
  Ints got(kLanes);
  ops().select_int(m.data(), a.data(), b.data(), got.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) ASSERT_EQ(got[k], m[k] ? a[k] : b[k]) << k;
}

TEST_P(VIntTest, Reductions) {
  auto a = random_ints(kLanes, 9, -100000, 100000);
  a[3] = kMin, a[width() + 1] = kMax;
  const int n = kLanes / width();
  Ints mn(n), mx(n), add(n);
  ops().int_reductions(a.data(), mn.data(), mx.data(), add.data(), kLanes);
  for (int v = 0; v < n; ++v) {
    std::int32_t want_min = kMax, want_max = kMin;
    std::int64_t want_add = 0;
    for (int k = v * width(); k < (v + 1) * width(); ++k) {
      want_min = std::min(want_min, a[k]);
      want_max = std::max(want_max, a[k]);
      want_add += a[k];
    }
    ASSERT_EQ(mn[v], want_min) << v;
    ASSERT_EQ(mx[v], want_max) << v;
    ASSERT_EQ(add[v], static_cast<std::int32_t>(static_cast<std::uint32_t>(want_add))) << v;  // wraps
  }
}

TEST_P(VIntTest, FloatToIntConversions) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> pattern = {0.5f, 1.5f, 2.5f, -0.5f, -2.5f, 2.75f, -2.75f, 1e10f,
                                      -1e10f, nan, 2147483520.0f, -2147483648.0f, -0.0f, 7.0f, -7.0f, 3.49f};
  const std::vector<std::int32_t> truncated = {0, 1, 2, 0, -2, 2, -2, kMin, kMin, kMin, 2147483520, kMin, 0, 7, -7, 3};
  const std::vector<std::int32_t> rounded = {0, 2, 2, 0, -2, 3, -3, kMin, kMin, kMin, 2147483520, kMin, 0, 7, -7, 3};
  std::vector<float> a(kLanes);
  for (int k = 0; k < kLanes; ++k) a[k] = pattern[k % pattern.size()];
  Ints trunc(kLanes), round(kLanes);
  ops().float_to_int(FloatToInt::Truncate, a.data(), trunc.data(), kLanes);
  ops().float_to_int(FloatToInt::Round, a.data(), round.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(trunc[k], truncated[k % pattern.size()]) << "truncate(" << a[k] << ")";
    ASSERT_EQ(round[k], rounded[k % pattern.size()]) << "round(" << a[k] << ")";
  }
  const auto r = floats_with_specials(kLanes, 10);
  for (FloatToInt op : {FloatToInt::Truncate, FloatToInt::Round, FloatToInt::Bits}) {
    Ints got(kLanes), want(kLanes);
    ops().float_to_int(op, r.data(), got.data(), kLanes);
    scalar().float_to_int(op, r.data(), want.data(), kLanes);
    EXPECT_TRUE(ints_match(got, want, "float to int vs scalar"));
  }
}

TEST_P(VIntTest, IntToFloatConversionsAndBitcasts) {
  auto a = random_ints(kLanes, 11, kMin, kMax);
  a[0] = kMax;  // rounds to 2^31
  std::vector<float> converted(kLanes), cast(kLanes);
  ops().int_to_float(IntToFloat::Convert, a.data(), converted.data(), kLanes);
  ops().int_to_float(IntToFloat::Bits, a.data(), cast.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(converted[k], static_cast<float>(a[k])) << a[k];
    ASSERT_EQ(std::bit_cast<std::int32_t>(cast[k]), a[k]) << k;
  }
  // Bits round trip: float -> int bits -> float keeps every bit, NaN included.
  const auto f = floats_with_specials(kLanes, 12);
  Ints bits(kLanes);
  std::vector<float> back(kLanes);
  ops().float_to_int(FloatToInt::Bits, f.data(), bits.data(), kLanes);
  ops().int_to_float(IntToFloat::Bits, bits.data(), back.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(bits[k], std::bit_cast<std::int32_t>(f[k])) << k;
    ASSERT_EQ(std::bit_cast<std::int32_t>(back[k]), bits[k]) << k;
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, VIntTest, ::testing::ValuesIn(all_isas()), isa_param_name);

}  // namespace
}  // namespace lancer::test
