// The one form of a reader's warnings: "lancer: warning: FILE: what", the form the
// commands use for theirs, so that a person (or a script) sees one kind of line.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace lancer {

// Prints each non-empty line of `text` as its own warning about `file` on stderr (a
// library's multi-line report becomes several lines, each with the prefix), trimmed of
// surrounding blanks.
void print_scene_warnings(const std::string& file, const std::string& text);

// While one is alive, every warning print_scene_warnings prints on this thread is also
// kept (without the "lancer: warning: FILE: " prefix), for the scene to list what its
// reader ignored (lancer info). Logs do not nest: an inner one takes over until it ends.
class SceneWarningLog {
 public:
  SceneWarningLog();
  ~SceneWarningLog();
  SceneWarningLog(const SceneWarningLog&) = delete;
  SceneWarningLog& operator=(const SceneWarningLog&) = delete;
  std::vector<std::string> take() { return std::move(lines_); }

 private:
  friend void print_scene_warnings(const std::string&, const std::string&);
  std::vector<std::string> lines_;
  SceneWarningLog* outer_;
};

}  // namespace lancer
