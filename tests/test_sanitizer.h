// Whether the test binary is built with AddressSanitizer, whose allocator replaces malloc
// and operator new and reserves terabytes of address space: tests of memory limits, of
// resident memory and of the program's own operator new skip themselves there.
#pragma once

namespace lancer::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitized = true;
#else
inline constexpr bool kAddressSanitized = false;
#endif
#else
inline constexpr bool kAddressSanitized = false;
#endif

}  // namespace lancer::test
