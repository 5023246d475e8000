// KHR_draco_mesh_compression end to end: a Draco-compressed copy of a mesh (encoded here
// with Draco's own encoder, lossless) renders the uncompressed mesh's image, and data that
// does not decode is refused with a message, never a crash.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "draco_test_encoder.h"
#include "gltf_mesh_scenes.h"
#include "image_estimate.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using test::lumpy_sphere;
using test::Mesh;
using test::render_lit_mesh;
using gltf_test::json;

// `m` as a triangle soup encoded by Draco (no quantization: lossless), and a glTF whose
// primitive points at it; the attributes' accessors have counts and no data, as the
// extension says.
GltfBuilder draco_copy(const Mesh& m) {
  const test::DracoEncoded encoded = test::draco_encode(m.positions, m.normals, m.uvs, m.indices);
  GltfBuilder b;
  const std::size_t points = encoded.points;
  const int view = b.add_view(encoded.bytes.data(), encoded.bytes.size());
  auto no_data = [&](int type, const char* kind, std::size_t count) {
    return b.push("accessors", {{"componentType", type}, {"count", count}, {"type", kind}});
  };
  json prim = {{"attributes",
                {{"POSITION", no_data(GltfBuilder::kFloat, "VEC3", points)},
                 {"NORMAL", no_data(GltfBuilder::kFloat, "VEC3", points)},
                 {"TEXCOORD_0", no_data(GltfBuilder::kFloat, "VEC2", points)}}},
               {"indices", no_data(GltfBuilder::kUInt, "SCALAR", m.indices.size())},
               {"mode", 4},
               {"extensions",
                {{"KHR_draco_mesh_compression",
                  {{"bufferView", view},
                   {"attributes",
                    {{"POSITION", encoded.position_id},
                     {"NORMAL", encoded.normal_id},
                     {"TEXCOORD_0", encoded.texcoord_id}}}}}}}};
  b.push("meshes", {{"primitives", json::array({prim})}});
  b.single_node_scene(0);
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return b;
}

class GltfDracoRender : public gltf_test::GltfTempDir {};

TEST_F(GltfDracoRender, CompressedCopyGivesTheSameImage) {
  const Mesh mesh = lumpy_sphere();
  test::write_float_copy(mesh, path("float.gltf"));
  draco_copy(mesh).write_data_uri_gltf(path("draco.gltf"));
  const Scene decoded = read_gltf(path("draco.gltf"));
  EXPECT_EQ(decoded.triangle_count(), read_gltf(path("float.gltf")).triangle_count());
  const ImageRGB reference = render_lit_mesh(path("float.gltf"));
  const ImageRGB compressed = render_lit_mesh(path("draco.gltf"));
  // Lossless: only the order of the triangles differs.
  EXPECT_LT(test::largest_block_difference(compressed, reference, 8), 1e-4);
  // The same as a .glb (whose JSON chunk the reader rewrites for tinygltf).
  const std::vector<unsigned char> glb = draco_copy(mesh).glb_bytes();
  gltf_test::write_file(path("draco.glb"), glb.data(), glb.size());
  EXPECT_LT(test::largest_block_difference(render_lit_mesh(path("draco.glb")), reference, 8), 1e-4);
}

TEST_F(GltfDracoRender, InstancesAreBoundedByTheDecodedFaces) {
  // 20,000 copies of the sphere (--instancing off): below the instanced-triangle limit
  // counted by its points (about 1,200 each), far above it by its 2,304 faces. The faces
  // count. Drawn through instances (the default) they are one sphere and 20,000 transforms.
  const Mesh mesh = lumpy_sphere();
  GltfBuilder b = draco_copy(mesh);
  const int zeros = b.push("accessors", {{"componentType", GltfBuilder::kFloat}, {"count", 20000}, {"type", "VEC3"}});
  b.doc["nodes"][0]["extensions"] = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", zeros}}}}}};
  b.doc["extensionsUsed"].push_back("EXT_mesh_gpu_instancing");
  b.write_data_uri_gltf(path("many.gltf"));
  const Scene shared = read_gltf(path("many.gltf"));
  EXPECT_EQ(shared.triangle_count(), 2304u);
  EXPECT_EQ(shared.instancing.instances.size(), 20000u);
  try {
    const Scene s = read_gltf(path("many.gltf"), -1, std::nullopt, InstancingMode::Off);
    ADD_FAILURE() << "made " << s.triangle_count() << " instanced triangles";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("20000 instances of a mesh of up to 2304 triangles exceed the limit"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(GltfDracoRender, DataThatDoesNotDecodeIsRefused) {
  GltfBuilder b = draco_copy(lumpy_sphere());
  for (std::size_t k = 0; k < b.bin.size(); k += 7) b.bin[k] = static_cast<unsigned char>(b.bin[k] ^ 0x5A);
  b.write_data_uri_gltf(path("broken.gltf"));
  try {
    const Scene s = read_gltf(path("broken.gltf"));
    ADD_FAILURE() << "loaded corrupted Draco data (" << s.triangle_count() << " triangles)";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("broken.gltf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("KHR_draco_mesh_compression: Draco data does not decode"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace lancer
