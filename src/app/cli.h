// The lancer command line: `lancer render`, `lancer info`, `lancer rays`, `lancer trace`,
// `lancer gen` and `lancer bench` (which runs the lancer-bench program).
// Kept out of main() so tests can run it in-process and check exit codes and messages.
#pragma once

#include <iosfwd>

namespace lancer {

// Exit codes: 0 success, 1 bad input or failure (message on `err`), 2 bad command line.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace lancer
