// Masks at every width: logic, the factories, movemask bit order and the reductions.
#include <bit>
#include <cstdint>
#include <vector>

#include "vector_ops_fixture.h"

namespace lancer::test {
namespace {

class VMaskTest : public VectorOpsTest {};

std::vector<std::int32_t> logic(const VectorOpsTable& t, MaskLogic op, const std::vector<std::int32_t>& a,
                                const std::vector<std::int32_t>& b) {
  std::vector<std::int32_t> out(a.size());
  t.mask_logic(op, a.data(), b.data(), out.data(), static_cast<int>(a.size()));
  return out;
}

TEST_P(VMaskTest, LogicFollowsTruthTables) {
  const auto a = random_mask(kLanes, 1), b = random_mask(kLanes, 2);
  const auto and_ = logic(ops(), MaskLogic::And, a, b), or_ = logic(ops(), MaskLogic::Or, a, b);
  const auto xor_ = logic(ops(), MaskLogic::Xor, a, b), andnot_ = logic(ops(), MaskLogic::Andnot, a, b);
  const auto not_ = logic(ops(), MaskLogic::Not, a, b);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(and_[k], a[k] & b[k]) << k;
    ASSERT_EQ(or_[k], a[k] | b[k]) << k;
    ASSERT_EQ(xor_[k], a[k] ^ b[k]) << k;
    ASSERT_EQ(andnot_[k], a[k] & (1 - b[k])) << k;  // a and not b
    ASSERT_EQ(not_[k], 1 - a[k]) << k;
  }
  for (MaskLogic op : {MaskLogic::And, MaskLogic::Or, MaskLogic::Xor, MaskLogic::Andnot, MaskLogic::Not})
    EXPECT_TRUE(ints_match(logic(ops(), op, a, b), logic(scalar(), op, a, b), "mask logic vs scalar"));
}

// Lane i is bit i, both ways: mask_from_bits and movemask are inverses.
TEST_P(VMaskTest, MovemaskBitOrderIsLaneOrder) {
  std::vector<std::int32_t> lanes(width());
  const int patterns = 1 << width();
  for (int bits = 0; bits < patterns; ++bits) {
    ops().mask_from_bits(bits, lanes.data());
    for (int k = 0; k < width(); ++k) ASSERT_EQ(lanes[k], (bits >> k) & 1) << "bits " << bits << " lane " << k;
    MaskReductions r{};
    ops().mask_reductions(lanes.data(), &r, width());
    ASSERT_EQ(r.movemask, bits);
  }
  // Only lane 0 set gives 1, only the last lane gives the top bit.
  std::vector<std::int32_t> first(width(), 0), last(width(), 0);
  first[0] = 1;
  last[width() - 1] = 1;
  MaskReductions r{};
  ops().mask_reductions(first.data(), &r, width());
  EXPECT_EQ(r.movemask, 1);
  ops().mask_reductions(last.data(), &r, width());
  EXPECT_EQ(r.movemask, 1 << (width() - 1));
}

TEST_P(VMaskTest, FirstLanesClampsCount) {
  std::vector<std::int32_t> lanes(width());
  for (int count = -3; count <= width() + 3; ++count) {
    ops().first_lanes(count, lanes.data());
    for (int k = 0; k < width(); ++k) ASSERT_EQ(lanes[k], k < count ? 1 : 0) << "count " << count << " lane " << k;
  }
}

TEST_P(VMaskTest, ReductionsCountActiveLanes) {
  auto m = random_mask(kLanes, 3);
  // Some vectors all off and some all on, so all() and none() are exercised both ways.
  for (int k = 0; k < width(); ++k) m[k] = 0, m[width() + k] = 1;
  const int n = kLanes / width();
  std::vector<MaskReductions> r(n);
  ops().mask_reductions(m.data(), r.data(), kLanes);
  for (int v = 0; v < n; ++v) {
    int bits = 0, count = 0;
    for (int k = 0; k < width(); ++k) {
      bits |= m[v * width() + k] << k;
      count += m[v * width() + k];
    }
    ASSERT_EQ(r[v].movemask, bits) << v;
    ASSERT_EQ(r[v].popcount, count) << v;
    ASSERT_EQ(r[v].any, count > 0) << v;
    ASSERT_EQ(r[v].all, count == width()) << v;
    ASSERT_EQ(r[v].none, count == 0) << v;
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, VMaskTest, ::testing::ValuesIn(all_isas()), isa_param_name);

}  // namespace
}  // namespace lancer::test
