// Paths tests read from: the project's scenes and the shared meshes beside the project.
#pragma once

#include <filesystem>

namespace lancer::test {

inline std::filesystem::path source_dir() { return LANCER_SOURCE_DIR; }
inline std::filesystem::path scenes_dir() { return source_dir() / "scenes"; }
// ../shared/scenes/models; tests that need it GTEST_SKIP() with a message when absent.
inline std::filesystem::path models_dir() { return LANCER_MODELS_DIR; }

}  // namespace lancer::test
