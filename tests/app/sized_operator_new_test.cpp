// The programs' operator new (src/app/sized_operator_new.cpp) throws OutOfMemory with the
// size asked for; the message a command prints names it.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <new>

#include "simd/out_of_memory.h"
#include "test_sanitizer.h"

namespace lancer {
namespace {

// 2^61 bytes: more than any address space, so malloc fails at once without a memory limit.
constexpr std::size_t kImpossible = std::size_t(1) << 61;

TEST(SizedOperatorNew, AFailedNewThrowsItsSize) {
  if (test::kAddressSanitized) GTEST_SKIP() << "AddressSanitizer brings its own operator new";
  for (int form = 0; form < 3; ++form) {
    try {
      void* p = form == 0   ? ::operator new(kImpossible)
                : form == 1 ? ::operator new[](kImpossible)
                            : ::operator new(kImpossible, std::align_val_t(64));
      ::operator delete(p);
      FAIL() << "form " << form << ": 2^61 bytes were allocated";
    } catch (const OutOfMemory& e) {
      EXPECT_EQ(e.bytes(), kImpossible) << "form " << form;
      EXPECT_EQ(out_of_memory_message(e), "out of memory: could not allocate 2147483648.00 GiB (2305843009213693952 bytes)");
    }
  }
}

TEST(SizedOperatorNew, NothrowFormsReturnNull) {
  if (test::kAddressSanitized) GTEST_SKIP() << "AddressSanitizer brings its own operator new";
  EXPECT_EQ(::operator new(kImpossible, std::nothrow), nullptr);
  EXPECT_EQ(::operator new(kImpossible, std::align_val_t(64), std::nothrow), nullptr);
  void* p = ::operator new(16, std::align_val_t(128));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 128, 0u);
  ::operator delete(p, std::align_val_t(128));
}

}  // namespace
}  // namespace lancer
