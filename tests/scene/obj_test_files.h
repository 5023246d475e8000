// A temporary folder per test for writing small OBJ/MTL/image files from test code.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "temp_dir.h"

namespace lancer::test {

class ObjFilesTest : public ::testing::Test {
 public:
  // Writes `content` byte for byte to dir/name and returns the path.
  std::filesystem::path write(const std::string& name, const std::string& content) const {
    const std::filesystem::path path = dir_ / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out << content;
    return path;
  }

  const std::filesystem::path& dir() const { return dir_; }

 private:
  TempDir temp_{"lancer_obj_test"};
  const std::filesystem::path& dir_ = temp_.path();
};

}  // namespace lancer::test
