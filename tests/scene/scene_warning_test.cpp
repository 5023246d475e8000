// Every reader warning has one form, "lancer: warning: FILE: what", a line each.
#include <gtest/gtest.h>

#include <string>

#include "scene/scene_warning.h"

namespace lancer {
namespace {

TEST(SceneWarning, OneLinePerMessageWithTheCommandsPrefix) {
  testing::internal::CaptureStderr();
  print_scene_warnings("model.gltf", "  first problem.\n\nsecond problem\r\n   \n");
  print_scene_warnings("model.gltf", "");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err,
            "lancer: warning: model.gltf: first problem.\n"
            "lancer: warning: model.gltf: second problem\n");
}

}  // namespace
}  // namespace lancer
