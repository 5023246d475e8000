// Starting a program from a test, its stdout and stderr to files, as the tests that run the
// real binaries (interrupts, mpirun) need.
#pragma once

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

namespace lancer::test {

// Forks and runs args[0] with `args`, stdout to `out` and stderr to `err`, its address
// space limited to `address_space` bytes (ulimit -v); returns the child's pid. The child
// exits 99 when it cannot open the files, 98 when exec fails, 97 when the limit is refused.
inline pid_t spawn(std::vector<std::string> args, const std::string& out, const std::string& err,
                   rlim_t address_space = RLIM_INFINITY) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (address_space != RLIM_INFINITY) {
      const rlimit limit{address_space, address_space};
      if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(97);
    }
    if (!freopen(out.c_str(), "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(99);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(98);
  }
  return pid;
}

}  // namespace lancer::test
