// Loads, stores and gathers at every width: aligned and unaligned copies, masked loads and
// stores that must not touch inactive lanes (checked against a guard page), and gathers with
// random indices.
#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "simd/aligned_vector.h"
#include "vector_ops_fixture.h"

namespace lancer::test {
namespace {

class VMemoryTest : public VectorOpsTest {};

TEST_P(VMemoryTest, AlignedAndUnalignedCopies) {
  const auto f = floats_with_specials(kLanes, 1);
  const auto i = random_ints(kLanes, 2, INT32_MIN, INT32_MAX);
  AlignedVector<float> src_f(f.begin(), f.end()), dst_f(kLanes + 8);
  AlignedVector<std::int32_t> src_i(i.begin(), i.end()), dst_i(kLanes + 8);

  ops().copy_float(true, src_f.data(), dst_f.data(), kLanes);
  ops().copy_int(true, src_i.data(), dst_i.data(), kLanes);
  EXPECT_EQ(std::memcmp(src_f.data(), dst_f.data(), kLanes * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(src_i.data(), dst_i.data(), kLanes * sizeof(std::int32_t)), 0);

  // Source and destination both off the vector alignment, by different amounts.
  const int n = kLanes - 16;
  ops().copy_float(false, src_f.data() + 1, dst_f.data() + 3, n);
  ops().copy_int(false, src_i.data() + 1, dst_i.data() + 3, n);
  EXPECT_EQ(std::memcmp(src_f.data() + 1, dst_f.data() + 3, n * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(src_i.data() + 1, dst_i.data() + 3, n * sizeof(std::int32_t)), 0);
}

TEST_P(VMemoryTest, MaskedLoadZeroesInactiveLanes) {
  const auto m = random_mask(kLanes, 3);
  const auto f = random_floats(kLanes, 4, 1.0f, 2.0f);
  const auto i = random_ints(kLanes, 5, 1, 1000);
  std::vector<float> out_f(kLanes);
  std::vector<std::int32_t> out_i(kLanes);
  ops().masked_load_float(m.data(), f.data() + 0, out_f.data(), kLanes);
  ops().masked_load_int(m.data(), i.data(), out_i.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(out_f[k], m[k] ? f[k] : 0.0f) << k;
    ASSERT_EQ(out_i[k], m[k] ? i[k] : 0) << k;
  }
}

TEST_P(VMemoryTest, MaskedStoreLeavesInactiveLanesUntouched) {
  const auto m = random_mask(kLanes, 6);
  const auto f = random_floats(kLanes, 7, 1.0f, 2.0f);
  const auto i = random_ints(kLanes, 8, 1, 1000);
  std::vector<float> dst_f(kLanes, -5.0f);
  std::vector<std::int32_t> dst_i(kLanes, -5);
  ops().masked_store_float(m.data(), f.data(), dst_f.data(), kLanes);
  ops().masked_store_int(m.data(), i.data(), dst_i.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(dst_f[k], m[k] ? f[k] : -5.0f) << k;
    ASSERT_EQ(dst_i[k], m[k] ? i[k] : -5) << k;
  }
}

#if defined(__linux__)
// A readable page followed by an inaccessible one: touching memory past the end faults.
class GuardedPage {
 public:
  GuardedPage() : size_(static_cast<std::size_t>(sysconf(_SC_PAGESIZE))) {
    void* p = mmap(nullptr, 2 * size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return;
    base_ = static_cast<char*>(p);
    if (mprotect(base_ + size_, size_, PROT_NONE) != 0) {
      munmap(base_, 2 * size_);
      base_ = nullptr;
    }
  }
  ~GuardedPage() {
    if (base_) munmap(base_, 2 * size_);
  }
  GuardedPage(const GuardedPage&) = delete;
  GuardedPage& operator=(const GuardedPage&) = delete;

  bool ok() const { return base_ != nullptr; }
  float* end() const { return reinterpret_cast<float*>(base_ + size_); }  // first inaccessible float
  std::size_t floats() const { return size_ / sizeof(float); }

 private:
  std::size_t size_;
  char* base_ = nullptr;
};

// The partial load/store of the last n < width elements of an array that ends at a page
// boundary: reading or writing the inactive lanes would crash here.
TEST_P(VMemoryTest, PartialLoadAndStoreAtPageEndStayInBounds) {
  GuardedPage page;
  ASSERT_TRUE(page.ok()) << "mmap/mprotect failed";
  float* first = page.end() - page.floats();
  for (std::size_t k = 0; k < page.floats(); ++k) first[k] = static_cast<float>(k);
  std::vector<float> out(width());
  for (int n = 0; n <= width(); ++n) {
    const float* src = page.end() - n;
    ops().load_first(src, n, out.data());
    for (int k = 0; k < width(); ++k) ASSERT_EQ(out[k], k < n ? src[k] : 0.0f) << "n " << n << " lane " << k;

    float* dst = page.end() - n;
    ops().store_first(-1.0f, n, dst);
    for (int k = 0; k < n; ++k) ASSERT_EQ(dst[k], -1.0f) << "n " << n << " lane " << k;
    // Elements just before the stored ones keep their values.
    const std::ptrdiff_t before = page.end() - first - n - 1;
    ASSERT_EQ(first[before], static_cast<float>(before)) << "n " << n;
    for (int k = 0; k < n; ++k) dst[k] = static_cast<float>(dst - first + k);  // restore
  }
}
#endif

TEST_P(VMemoryTest, GatherRandomIndicesMatchesScalar) {
  const auto table_f = floats_with_specials(4096, 9);
  const auto table_i = random_ints(4096, 10, INT32_MIN, INT32_MAX);
  const auto index = random_ints(kLanes, 11, 0, 4095);
  std::vector<float> got_f(kLanes), want_f(kLanes);
  std::vector<std::int32_t> got_i(kLanes), want_i(kLanes);
  ops().gather_float(table_f.data(), index.data(), nullptr, got_f.data(), kLanes);
  scalar().gather_float(table_f.data(), index.data(), nullptr, want_f.data(), kLanes);
  ops().gather_int(table_i.data(), index.data(), nullptr, got_i.data(), kLanes);
  scalar().gather_int(table_i.data(), index.data(), nullptr, want_i.data(), kLanes);
  EXPECT_TRUE(floats_match(got_f, want_f, "gather float"));
  EXPECT_TRUE(ints_match(got_i, want_i, "gather int"));
  for (int k = 0; k < kLanes; ++k) ASSERT_EQ(got_i[k], table_i[index[k]]) << k;

  // Negative indices reach before the base pointer.
  const float* middle = table_f.data() + 2048;
  std::vector<std::int32_t> signed_index = random_ints(kLanes, 12, -2048, 2047);
  ops().gather_float(middle, signed_index.data(), nullptr, got_f.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) ASSERT_TRUE(same_float(got_f[k], middle[signed_index[k]])) << k;
}

// Inactive lanes carry indices far outside any allocation: dereferencing one would crash.
TEST_P(VMemoryTest, MaskedGatherSkipsInactiveLanes) {
  const auto table_f = random_floats(256, 13, 1.0f, 2.0f);
  const auto table_i = random_ints(256, 14, 1, 1000);
  const auto m = random_mask(kLanes, 15);
  auto index = random_ints(kLanes, 16, 0, 255);
  for (int k = 0; k < kLanes; ++k)
    if (!m[k]) index[k] = (k % 2) ? INT32_MAX : INT32_MIN;
  std::vector<float> got_f(kLanes);
  std::vector<std::int32_t> got_i(kLanes);
  ops().gather_float(table_f.data(), index.data(), m.data(), got_f.data(), kLanes);
  ops().gather_int(table_i.data(), index.data(), m.data(), got_i.data(), kLanes);
  for (int k = 0; k < kLanes; ++k) {
    ASSERT_EQ(got_f[k], m[k] ? table_f[index[k]] : 0.0f) << k;
    ASSERT_EQ(got_i[k], m[k] ? table_i[index[k]] : 0) << k;
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, VMemoryTest, ::testing::ValuesIn(all_isas()), isa_param_name);

}  // namespace
}  // namespace lancer::test
