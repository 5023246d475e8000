// A folder of a test's own under the system's temporary directory: named after `prefix`, the
// process and a serial number, made empty on creation and removed with everything in it on
// destruction, also when a failed assertion ends the test early (ctest runs every test in a
// process of its own, so a folder left behind would be one more per test and run).
#pragma once

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

namespace lancer::test {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix)
      : path_(std::filesystem::temp_directory_path() /
              (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(next_serial()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

 private:
  static int next_serial() {
    static std::atomic<int> serial{0};
    return serial++;
  }
  std::filesystem::path path_;
};

}  // namespace lancer::test
