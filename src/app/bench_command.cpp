#include "app/bench_command.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <ostream>
#include <stdexcept>
#include <system_error>

namespace lancer {

std::filesystem::path bench_program_path() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the running lancer binary (/proc/self/exe): " + ec.message());
  return self.parent_path() / kBenchProgramName;
}

int exec_bench_program(const std::filesystem::path& program, const std::vector<std::string>& args, std::ostream& err) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(program, ec)) {
    err << "lancer: error: " << program.string() << " not found: `lancer bench` runs the " << kBenchProgramName
        << " program from the directory of lancer. Build it with `cmake --build <build dir> --target "
        << kBenchProgramName << "` (it is part of the benchmarks, LANCER_BUILD_BENCH=ON), or run `make bench`.\n";
    return 1;
  }
  const std::string path = program.string();
  std::vector<char*> argv;
  argv.reserve(args.size() + 2);
  argv.push_back(const_cast<char*>(path.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::cout.flush();  // nothing buffered may be lost when the process image is replaced
  std::cerr.flush();
  ::execv(path.c_str(), argv.data());
  const int error = errno;  // execv returns only on failure
  err << "lancer: error: cannot run " << path << ": " << std::strerror(error) << "\n";
  return 1;
}

int run_bench(const std::vector<std::string>& args, std::ostream& err) {
  try {
    return exec_bench_program(bench_program_path(), args, err);
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace lancer
