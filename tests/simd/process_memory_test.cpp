// resident_bytes / peak_resident_bytes follow what the process touches.
#include "simd/process_memory.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

namespace lancer {
namespace {

TEST(ProcessMemory, PeakFollowsTouchedMemory) {
  const std::int64_t resident = resident_bytes(), peak = peak_resident_bytes();
  if (resident < 0) GTEST_SKIP() << "no /proc/self/status here";
  EXPECT_GT(resident, 0);
  EXPECT_GE(peak, resident);
  constexpr std::size_t kBytes = std::size_t(96) << 20;
  {
    const std::unique_ptr<char[]> block(new char[kBytes]);
    std::memset(block.get(), 1, kBytes);  // touched: resident
    asm volatile("" : : "r"(block.get()) : "memory");  // the stores may not be optimised away
    EXPECT_GE(resident_bytes(), resident + std::int64_t(kBytes) - (std::int64_t(8) << 20));
  }
  EXPECT_GE(peak_resident_bytes(), resident + std::int64_t(kBytes) - (std::int64_t(8) << 20))
      << "the peak keeps the 96 MiB after they are freed";
}

}  // namespace
}  // namespace lancer
