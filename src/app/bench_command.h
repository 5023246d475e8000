// `lancer bench ...`: runs `lancer-bench`, the separate benchmark program that sits next to
// `lancer` (it links Embree 3 when found, which the renderer never does), with every
// argument after `bench` passed through unchanged.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace lancer {

inline constexpr const char* kBenchProgramName = "lancer-bench";

// The benchmark program beside the running lancer binary (/proc/self/exe). Throws
// std::runtime_error when the running binary cannot be found.
std::filesystem::path bench_program_path();

// Replaces this process with `program args...` (execv). Returns only on failure: the exit
// code 1, with a message on `err` naming the path and what to build when the program is
// missing or cannot be run.
int exec_bench_program(const std::filesystem::path& program, const std::vector<std::string>& args, std::ostream& err);

// bench_program_path() then exec_bench_program(); returns only on failure.
int run_bench(const std::vector<std::string>& args, std::ostream& err);

}  // namespace lancer
