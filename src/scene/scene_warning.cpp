#include "scene/scene_warning.h"

#include <iostream>
#include <sstream>

namespace lancer {

void print_scene_warnings(const std::string& file, const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const auto first = line.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) continue;
    const auto last = line.find_last_not_of(" \t\r\n");
    std::cerr << "lancer: warning: " << file << ": " << line.substr(first, last - first + 1) << '\n';
  }
}

}  // namespace lancer
