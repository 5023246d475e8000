# Warning and optimisation flags as INTERFACE targets, so each library opts in
# explicitly and no ISA flag leaks into generic code (ISA flags go on single files).
add_library(lancer_warnings INTERFACE)
target_compile_options(lancer_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-missing-field-initializers)

add_library(lancer_options INTERFACE)
# The generic code targets the x86-64 baseline plus SSE4.2, the minimum Lancer runs on.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  target_compile_options(lancer_options INTERFACE -msse4.2)
endif()
# Same arithmetic on every path: no silent fused multiply-adds in generic code.
target_compile_options(lancer_options INTERFACE -ffp-contract=off)
# Nothing reads errno after a maths call: sqrt and friends become single instructions with
# no error branch and no call (the results are the same IEEE values).
target_compile_options(lancer_options INTERFACE -fno-math-errno)
if(LANCER_SANITIZE OR LANCER_FUZZ)
  target_compile_options(lancer_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(lancer_options INTERFACE -fsanitize=address,undefined)
endif()
if(LANCER_FUZZ)
  # Coverage feedback for libFuzzer in every library; only the fuzz targets themselves
  # link libFuzzer's main (tests/fuzz/CMakeLists.txt).
  target_compile_options(lancer_options INTERFACE -fsanitize=fuzzer-no-link)
endif()
