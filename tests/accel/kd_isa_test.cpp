// Choosing the kd-tree's traversal ISA: the default, forcing one, refusing one the CPU lacks,
// and the leaf block width that goes with each.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "accel/kd_traverse.h"
#include "accel/kd_tree.h"
#include "kd_test_support.h"

namespace lancer::test {
namespace {

TEST(KdIsa, DefaultIsTheBestSupported) {
  const TriangleSoA t = random_soup(100, 1, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  EXPECT_EQ(KdTree(t).isa(), best_supported_isa());
}

// Every ISA: the tree uses it and lays its blocks out at the kernels' width, or, where the
// CPU lacks it, the constructor says so.
TEST(KdIsa, ForcedIsaOrClearRefusal) {
  const TriangleSoA t = random_soup(100, 2, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  const int vector_width[] = {1, 4, 8, 16};  // Scalar, Sse4, Avx2, Avx512
  for (Isa isa : kd_test_isas()) {
    SCOPED_TRACE(std::string(isa_name(isa)));
    if (!cpu_supports(isa)) {
      try {
        const KdTree kd(t, {}, isa);
        ADD_FAILURE() << "built a tree for an ISA this CPU lacks";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(isa_name(isa)), std::string::npos) << e.what();
      }
      continue;
    }
    const KdTree kd(t, {}, isa);
    EXPECT_EQ(kd.isa(), isa);
    const KdKernels k = select_kd_kernels(isa);
    EXPECT_EQ(k.isa, isa);
    EXPECT_EQ(kd.block_width(), k.block_width);
    EXPECT_EQ(k.block_width % vector_width[static_cast<int>(isa)], 0);
    EXPECT_EQ(kd.leaf_prims().size() % std::size_t(k.block_width), 0u);
    EXPECT_EQ(kd.blocks().size(), kd.leaf_prims().size() * 9);
  }
}

}  // namespace
}  // namespace lancer::test
