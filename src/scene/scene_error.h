// The one exception readers throw: the message names the file and what is wrong.
#pragma once

#include <stdexcept>
#include <string>

namespace lancer {

class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, const std::string& what) : std::runtime_error(file + ": " + what) {}
};

}  // namespace lancer
