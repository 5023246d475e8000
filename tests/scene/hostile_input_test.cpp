// Regression tests for what fuzzing and review of the readers found (tests/fuzz): each
// input once crashed, hung or gave a misleading error, and must now be a SceneError
// naming the file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>
#include <vector>

#include "gltf_test_files.h"
#include "scene/gltf_reader.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;

class HostileGltf : public gltf_test::GltfTempDir {
 protected:
  void expect_scene_error(const std::filesystem::path& file, const std::string& word) {
    testing::internal::CaptureStderr();
    try {
      const Scene s = read_gltf(file);
      ADD_FAILURE() << file << " loaded (" << s.triangle_count() << " triangles), expected an error";
    } catch (const SceneError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << "expected '" << word << "' in: " << msg;
    }
    testing::internal::GetCapturedStderr();
  }
};

GltfBuilder triangle() {
  GltfBuilder b;
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3(gltf_test::unit_triangle())}}));
  return b;
}

// tinygltf's own file reader took a directory for a file of 2^63 bytes: std::bad_alloc
// in a normal build, an allocation-size abort under AddressSanitizer.
TEST_F(HostileGltf, BufferUriNamingADirectory) {
  std::filesystem::create_directories(path("folder.bin"));
  gltf_test::write_text(path("scene.gltf"), triangle().json_text("folder.bin"));
  expect_scene_error(path("scene.gltf"), "folder.bin");
}

TEST_F(HostileGltf, ImageUriNamingADirectory) {
  GltfBuilder b = triangle();
  b.push("images", {{"uri", "."}});
  b.push("textures", {{"source", 0}});
  b.write_data_uri_gltf(path("scene.gltf"));
  expect_scene_error(path("scene.gltf"), "image 0");
}

// tinygltf's FileExists called fopen, which blocks until a FIFO gets a writer: the load
// hung for ever. (If this regresses, the test hangs until ctest's timeout.)
TEST_F(HostileGltf, BufferUriNamingAFifo) {
  ASSERT_EQ(::mkfifo(path("pipe.bin").c_str(), 0600), 0);
  gltf_test::write_text(path("scene.gltf"), triangle().json_text("pipe.bin"));
  expect_scene_error(path("scene.gltf"), "pipe.bin");
}

// The in-memory entry point the fuzz target uses gives the same answers as the file one.
TEST_F(HostileGltf, BytesEntryPointMatchesFileEntryPoint) {
  const std::vector<unsigned char> glb = triangle().glb_bytes();
  EXPECT_EQ(read_gltf_bytes(glb, path("memory.glb")).triangle_count(), 1u);
  const std::string text = triangle().json_text("data:application/octet-stream;base64," +
                                                gltf_test::base64(triangle().bin));
  const std::vector<unsigned char> json(text.begin(), text.end());
  EXPECT_EQ(read_gltf_bytes(json, path("memory.gltf")).triangle_count(), 1u);
  try {
    (void)read_gltf_bytes(json, path("memory.glb"));
    ADD_FAILURE() << "JSON accepted as a .glb";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("memory.glb"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_gltf_bytes({}, path("empty.gltf")), SceneError);
}

}  // namespace
}  // namespace lancer
