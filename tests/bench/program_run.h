// Running a program of the project as a user would, for the end-to-end bench tests: its
// exit code, stdout and stderr, through /bin/sh with the outputs kept in a folder.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace lancer::test {

struct ProgramResult {
  int code = -1;  // the exit status, -1 when the program did not exit normally
  std::string out, err;
};

inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `command` (a program and its arguments, as the shell reads them) with its stdout
// and stderr in out.txt and err.txt of `dir`.
inline ProgramResult run_program(const std::string& command, const std::filesystem::path& dir) {
  const int status = std::system((command + " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string()).c_str());
  ProgramResult r;
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.out = file_text(dir / "out.txt");
  r.err = file_text(dir / "err.txt");
  return r;
}

}  // namespace lancer::test
