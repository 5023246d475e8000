// The one form of a reader's warnings: "lancer: warning: FILE: what", the form the
// commands use for theirs, so that a person (or a script) sees one kind of line.
#pragma once

#include <string>

namespace lancer {

// Prints each non-empty line of `text` as its own warning about `file` on stderr (a
// library's multi-line report becomes several lines, each with the prefix), trimmed of
// surrounding blanks.
void print_scene_warnings(const std::string& file, const std::string& text);

}  // namespace lancer
