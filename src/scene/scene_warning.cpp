#include "scene/scene_warning.h"

#include <iostream>
#include <sstream>

namespace lancer {

namespace {
thread_local SceneWarningLog* active_log = nullptr;
}  // namespace

SceneWarningLog::SceneWarningLog() : outer_(active_log) { active_log = this; }
SceneWarningLog::~SceneWarningLog() { active_log = outer_; }

void print_scene_warnings(const std::string& file, const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const auto first = line.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) continue;
    const auto last = line.find_last_not_of(" \t\r\n");
    const std::string what = line.substr(first, last - first + 1);
    std::cerr << "lancer: warning: " << file << ": " << what << '\n';
    if (active_log != nullptr) active_log->lines_.push_back(what);
  }
}

}  // namespace lancer
