// glTF reader on bad input: every case must throw SceneError naming the file and
// saying what is wrong, never crash, hang or allocate without bound.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using gltf_test::unit_triangle;

// One indexed triangle: accessor 0 = POSITION over bufferView 0 (36 bytes),
// accessor 1 = uint16 indices over bufferView 1, mesh 0, node 0, scene 0.
GltfBuilder base_triangle() {
  GltfBuilder b;
  const int pos = b.add_vec3(unit_triangle());
  const int idx = b.add_indices(std::vector<std::uint16_t>{0, 1, 2});
  b.single_node_scene(b.add_mesh({{"POSITION", pos}}, 4, idx));
  return b;
}

class GltfErrors : public gltf_test::GltfTempDir {};

TEST_F(GltfErrors, BaseTriangleIsValid) {
  // The mutations below start from this file, so it must load.
  base_triangle().write_data_uri_gltf(path("good.gltf"));
  EXPECT_EQ(read_gltf(path("good.gltf")).triangle_count(), 1u);
}

TEST_F(GltfErrors, MissingEmptyAndInvalidFiles) {
  expect_error(path("missing.gltf"), "no such file");
  gltf_test::write_text(path("empty.gltf"), "");
  expect_error(path("empty.gltf"), "empty file");
  gltf_test::write_text(path("json.gltf"), "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  expect_error(path("json.gltf"), "invalid JSON");
  gltf_test::write_text(path("array.gltf"), "[1, 2, 3]");
  expect_error(path("array.gltf"), "not an object");
  gltf_test::write_text(path("text.glb"), "{\"asset\": {\"version\": \"2.0\"}}");
  expect_error(path("text.glb"), "bad magic");
  gltf_test::write_text(path("noasset.gltf"), "{\"nodes\": []}");
  expect_error(path("noasset.gltf"), "asset");
}

TEST_F(GltfErrors, WrongJsonTypes) {
  GltfBuilder b = base_triangle();
  b.doc["meshes"][0]["primitives"][0]["indices"] = "1";
  expect_error(b, "wrong JSON type: meshes[0].primitives[0].indices");
  b = base_triangle();
  b.doc["accessors"][0]["count"] = "three";
  expect_error(b, "wrong JSON type: accessors[0].count");
  b = base_triangle();
  b.doc["nodes"] = {{"mesh", 0}};  // an object, not an array
  expect_error(b, "wrong JSON type: nodes");
  b = base_triangle();
  b.doc["nodes"][0]["mesh"] = 4294967296.0 * 2;  // not an integer index
  expect_error(b, "wrong JSON type: nodes[0].mesh");
  b = base_triangle();
  b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = -1;
  expect_error(b, "wrong JSON type: meshes[0].primitives[0].attributes.POSITION");
  b = base_triangle();
  b.doc["meshes"][0]["primitives"][0].erase("attributes");
  expect_error(b, "attributes");
  b = base_triangle();
  b.doc["bufferViews"][0].erase("byteLength");  // reported by tinygltf
  expect_error(b, "byteLength");
}

TEST_F(GltfErrors, DeeplyNestedJsonIsRefusedNotOverflowingTheStack) {
  const GltfBuilder b = base_triangle();
  const std::string text = b.json_text("data:application/octet-stream;base64," + gltf_test::base64(b.bin));
  auto nested = [](std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  gltf_test::write_text(path("shallow.gltf"), "{\"extras\": " + nested(20) + "," + text.substr(1));
  EXPECT_EQ(read_gltf(path("shallow.gltf")).triangle_count(), 1u);
  gltf_test::write_text(path("deep.gltf"), "{\"extras\": " + nested(200000) + "," + text.substr(1));
  expect_error(path("deep.gltf"), "nested deeper than");
}

TEST_F(GltfErrors, UnsupportedRequiredExtensionIsNamed) {
  GltfBuilder b = base_triangle();
  b.doc["extensionsUsed"] = {"KHR_texture_basisu"};
  b.doc["extensionsRequired"] = {"KHR_materials_ior", "KHR_texture_basisu"};
  expect_error(b, "'KHR_texture_basisu' is not supported");
  b.write_glb(path("basisu.glb"));
  expect_error(path("basisu.glb"), "KHR_texture_basisu");
}

TEST_F(GltfErrors, MissingAndShortBufferFiles) {
  const GltfBuilder b = base_triangle();
  b.write_external_gltf(path("ext.gltf"), "ext.bin");
  std::filesystem::remove(path("ext.bin"));
  expect_error(path("ext.gltf"), "not found");
  const std::vector<unsigned char> short_bin(b.bin.begin(), b.bin.end() - 4);
  gltf_test::write_file(path("ext.bin"), short_bin.data(), short_bin.size());
  expect_error(path("ext.gltf"), "size mismatch");
}

TEST_F(GltfErrors, IndicesAndReferencesOutOfRange) {
  GltfBuilder b;
  const int pos = b.add_vec3(unit_triangle());
  b.single_node_scene(b.add_mesh({{"POSITION", pos}}, 4, b.add_indices(std::vector<std::uint32_t>{0, 1, 3})));
  expect_error(b, "index 3 at position 2 is out of range");

  struct Case {
    const char* what;
    void (*mutate)(json&);
    const char* word;
  };
  const Case cases[] = {
      {"POSITION accessor", [](json& d) { d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 42; },
       "accessor index 42 out of range"},
      {"indices accessor", [](json& d) { d["meshes"][0]["primitives"][0]["indices"] = 42; }, "accessor"},
      {"bufferView", [](json& d) { d["accessors"][0]["bufferView"] = 9; }, "bufferView index 9 out of range"},
      {"buffer", [](json& d) { d["bufferViews"][0]["buffer"] = 3; }, "buffer 3, out of range"},
      {"material", [](json& d) { d["meshes"][0]["primitives"][0]["material"] = 5; }, "material index 5 out of range"},
      {"mesh", [](json& d) { d["nodes"][0]["mesh"] = 5; }, "mesh index 5 out of range"},
      {"camera", [](json& d) { d["nodes"][0]["camera"] = 2; }, "camera index 2 out of range"},
      {"child", [](json& d) { d["nodes"][0]["children"] = {7}; }, "child index 7 out of range"},
      {"scene node", [](json& d) { d["scenes"][0]["nodes"] = {7}; }, "node index 7 out of range"},
      {"default scene", [](json& d) { d["scene"] = 3; }, "default scene 3 out of range"},
      {"texture",
       [](json& d) {
         d["materials"] = {{{"emissiveTexture", {{"index", 4}}}}};
       },
       "texture index 4"},
      {"image",
       [](json& d) {
         d["textures"] = {{{"source", 2}}};
       },
       "image index 2 out of range"},
      {"sampler",
       [](json& d) {
         d["textures"] = {{{"sampler", 2}}};
       },
       "sampler index 2 out of range"},
      {"light", [](json& d) { d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 3; },
       "light index 3 out of range"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    GltfBuilder bad = base_triangle();
    c.mutate(bad.doc);
    expect_error(bad, c.word);
  }
}

TEST_F(GltfErrors, DataRunningPastItsBuffer) {
  GltfBuilder b = base_triangle();
  b.doc["accessors"][0]["byteOffset"] = 4;  // 36 bytes from offset 4 in a 36-byte view
  expect_error(b, "runs past the end of its bufferView");
  b = base_triangle();
  b.doc["bufferViews"][1]["byteLength"] = 1000;
  expect_error(b, "runs past the end of buffer 0");
  b = base_triangle();
  b.doc["bufferViews"][0]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 8;  // offset + length wraps
  expect_error(b, "runs past the end of buffer 0");
  b = base_triangle();
  b.doc["accessors"][0]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 8;
  expect_error(b, "runs past the end of its bufferView");
}

TEST_F(GltfErrors, HugeCountsAreRefusedBeforeAllocating) {
  GltfBuilder b = base_triangle();
  b.doc["accessors"][0]["count"] = std::uint64_t(1) << 32;
  expect_error(b, "runs past the end of its bufferView");
  b = base_triangle();
  b.doc["accessors"][1]["count"] = (std::uint64_t(1) << 32) * 3;
  expect_error(b, "runs past the end of its bufferView");
  b = base_triangle();
  b.doc["accessors"][0]["count"] = std::numeric_limits<std::uint64_t>::max() / 2;  // stride * count overflows
  expect_error(b, "runs past the end of its bufferView");
  b = base_triangle();
  b.doc["accessors"][0].erase("bufferView");
  b.doc["accessors"][0]["count"] = std::uint64_t(1) << 32;
  expect_error(b, "has no bufferView and claims 4294967296 elements");
}

TEST_F(GltfErrors, BadByteStride) {
  GltfBuilder b = base_triangle();
  b.doc["bufferViews"][0]["byteStride"] = 8;  // below the 12-byte VEC3 element
  expect_error(b, "bad byteStride 8, smaller than the element size 12");
  for (int stride : {14, 256}) {  // not a multiple of 4, above 252: tinygltf refuses
    b = base_triangle();
    b.doc["bufferViews"][0]["byteStride"] = stride;
    expect_error(b, "byteStride");
  }
}

TEST_F(GltfErrors, WrongAccessorTypesForAttributes) {
  GltfBuilder b = base_triangle();
  b.doc["accessors"][0]["type"] = "VEC2";
  expect_error(b, "POSITION (accessor 0) must be VEC3 of FLOAT (integers need the file to use KHR_mesh_quantization), but it is VEC2 of FLOAT");
  b = base_triangle();
  b.doc["accessors"][0]["componentType"] = GltfBuilder::kUShort;
  expect_error(b, "must be VEC3 of FLOAT (integers need the file to use KHR_mesh_quantization), but it is VEC3 of UNSIGNED_SHORT");
  b = base_triangle();
  b.doc["accessors"][1]["componentType"] = GltfBuilder::kFloat;
  expect_error(b, "indices (accessor 1) must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  b = base_triangle();
  b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 1;  // the SCALAR indices
  expect_error(b, "NORMAL (accessor 1) must be VEC3 of FLOAT (integers need the file to use KHR_mesh_quantization)");
  // TEXCOORD_0 as UNSIGNED_BYTE must be normalized.
  b = base_triangle();
  const std::vector<std::uint8_t> uv = {0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0};
  const int acc = b.add_accessor(b.add_view(uv.data(), uv.size(), 4), GltfBuilder::kUByte, 3, "VEC2");
  b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = acc;
  expect_error(b, "TEXCOORD_0 (accessor 2) must be VEC2 of FLOAT or of normalized");
  // Attribute counts must agree.
  b = base_triangle();
  const int two = b.add_vec3({{0, 0, 1}, {0, 0, 1}});
  b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = two;
  expect_error(b, "NORMAL has 2 elements but POSITION has 3");
  b = base_triangle();
  b.doc["meshes"][0]["primitives"][0]["attributes"] = json::object({{"NORMAL", 0}});
  expect_error(b, "has no POSITION attribute");
}

TEST_F(GltfErrors, BadSparseAccessors) {
  auto sparse_triangle = [](int count, std::uint16_t target, std::size_t value_bytes) {
    GltfBuilder b = base_triangle();
    const std::vector<std::uint16_t> which = {target, target};
    const std::vector<float> values(9, 1.0f);  // room for the largest value_bytes below
    b.doc["accessors"][0]["sparse"] = {
        {"count", count},
        {"indices", {{"bufferView", b.add_view(which.data(), 4)}, {"componentType", GltfBuilder::kUShort}}},
        {"values", {{"bufferView", b.add_view(values.data(), value_bytes)}}}};
    return b;
  };
  expect_error(sparse_triangle(1, 7, 12), "sparse index 7 out of range");
  expect_error(sparse_triangle(5, 0, 12), "sparse count 5 out of range");
  expect_error(sparse_triangle(2, 0, 12), "sparse values run past the end of their bufferView");
  expect_error(sparse_triangle(3, 0, 36), "sparse indices run past the end of their bufferView");
}

TEST_F(GltfErrors, NonFinitePositions) {
  GltfBuilder b;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}})}}));
  expect_error(b, "non-finite");
  GltfBuilder c;
  const float inf = std::numeric_limits<float>::infinity();
  c.single_node_scene(c.add_mesh({{"POSITION", c.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, inf, 0}})}}));
  expect_error(c, "non-finite");
}

TEST_F(GltfErrors, NodeHierarchyCyclesAndSharedNodes) {
  GltfBuilder b = base_triangle();
  b.doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
  b.doc.erase("scenes");
  b.doc.erase("scene");
  expect_error(b, "cycle");
  b.doc["nodes"] = {{{"mesh", 0}, {"children", {0}}}};
  expect_error(b, "cycle");
  // A cycle entered from a root gives its entry node two parents.
  b.doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {2}}}, {{"children", {1}}}};
  expect_error(b, "not a tree");
  b.doc["nodes"] = {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
  expect_error(b, "node 2 is a child of both node 0 and node 1");
  b = base_triangle();
  b.doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"mesh", 0}}};
  b.doc["scenes"][0]["nodes"] = {0, 1};
  expect_error(b, "scene nodes must be roots");
  b.doc["scenes"][0]["nodes"] = {0, 0};
  expect_error(b, "lists node 0 twice");
}

TEST_F(GltfErrors, BadPrimitivesMaterialsImagesCamerasAndLights) {
  struct Case {
    const char* what;
    void (*mutate)(json&);
    const char* word;
  };
  const Case cases[] = {
      {"mode", [](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 9; }, "unknown primitive mode 9"},
      {"triangle count", [](json& d) { d["accessors"][1]["count"] = 2; }, "2 vertices, not a multiple of 3"},
      {"alphaMode",
       [](json& d) {
         d["materials"] = {{{"alphaMode", "SHINY"}}};
       },
       "unknown alphaMode 'SHINY'"},
      {"extension type",
       [](json& d) {
         d["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", "high"}}}}}}};
       },
       "wrong JSON type: materials[0].extensions.KHR_materials_ior.ior must be a number"},
      {"image data",
       [](json& d) {
         d["images"] = {{{"uri", "data:image/png;base64,AAECAwQFBgcICQ=="}}};
       },
       "cannot be decoded"},
      {"image file",
       [](json& d) {
         d["images"] = {{{"uri", "no_such_image.png"}}};
       },
       "could not be read"},
      {"yfov",
       [](json& d) {
         d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", -1.0}, {"znear", 0.1}}}}};
         d["nodes"][0]["camera"] = 0;
       },
       "yfov"},
      {"light type",
       [](json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "area"}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "unknown KHR_lights_punctual type 'area'"},
      {"spot cone",
       [](json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {
             {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.9}, {"outerConeAngle", 0.5}}}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "cone angles"},
      {"matrix size",
       [](json& d) {
         d["nodes"][0]["matrix"] = {1, 0, 0};
       },
       "matrix has 3 numbers, not 16"},
      {"rotation",
       [](json& d) {
         d["nodes"][0]["rotation"] = {0, 0, 0, 0};
       },
       "rotation quaternion"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    GltfBuilder bad = base_triangle();
    c.mutate(bad.doc);
    expect_error(bad, c.word);
  }
}

TEST_F(GltfErrors, MalformedGlbContainers) {
  const std::vector<unsigned char> good = base_triangle().glb_bytes();
  auto write_variant = [&](const char* name, void (*mutate)(std::vector<unsigned char>&)) {
    std::vector<unsigned char> bytes = good;
    mutate(bytes);
    gltf_test::write_file(path(name), bytes.data(), bytes.size());
    return path(name);
  };
  expect_error(write_variant("v1.glb", [](std::vector<unsigned char>& v) { v[4] = 1; }), "version 1");
  expect_error(write_variant("len.glb", [](std::vector<unsigned char>& v) { v[11] = 0x7f; }), "truncated");
  expect_error(write_variant("json.glb", [](std::vector<unsigned char>& v) { v[15] = 0x7f; }), "JSON chunk runs past");
  expect_error(write_variant("type.glb", [](std::vector<unsigned char>& v) { v[16] = 'X'; }), "not JSON");
  // A buffer claiming more bytes than the BIN chunk holds (reported by tinygltf).
  GltfBuilder c = base_triangle();
  std::vector<unsigned char> glb = c.glb_bytes();
  // Shrink the BIN chunk by 4 bytes: the chunk length and total length both drop.
  auto put32 = [&](std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) glb[at + std::size_t(k)] = (v >> (8 * k)) & 255;
  };
  auto get32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | glb[at + std::size_t(k)];
    return v;
  };
  const std::size_t bin_header = 20 + get32(12);
  put32(bin_header, get32(bin_header) - 4);
  put32(8, get32(8) - 4);
  glb.resize(glb.size() - 4);
  gltf_test::write_file(path("bin.glb"), glb.data(), glb.size());
  expect_error(path("bin.glb"), "byteLength");
  // A BIN chunk declaring more bytes than the file holds, the header's total length still
  // within the file (found by fuzzing: tinygltf read past the end of the data).
  std::vector<unsigned char> over = good;
  over.push_back(0);  // one byte beyond the declared total length
  const std::size_t over_bin = 20 + (std::uint32_t(over[12]) | std::uint32_t(over[13]) << 8 |
                                     std::uint32_t(over[14]) << 16 | std::uint32_t(over[15]) << 24);
  over[over_bin] = static_cast<unsigned char>(over[over_bin] + 4);
  gltf_test::write_file(path("binlong.glb"), over.data(), over.size());
  expect_error(path("binlong.glb"), "the chunk after the JSON chunk declares");
}

// Every strict prefix of a valid file is an error with a message, never a crash.
TEST_F(GltfErrors, TruncatedFilesAtEveryCutPoint) {
  const GltfBuilder b = base_triangle();
  const std::string text = b.json_text("data:application/octet-stream;base64," + gltf_test::base64(b.bin));
  for (std::size_t cut = 0; cut < text.size(); ++cut) {
    SCOPED_TRACE(".gltf cut at " + std::to_string(cut) + " of " + std::to_string(text.size()));
    gltf_test::write_text(path("cut.gltf"), text.substr(0, cut));
    expect_error(path("cut.gltf"), cut == 0 ? "empty file" : "invalid JSON");
  }
  const std::vector<unsigned char> glb = b.glb_bytes();
  for (std::size_t cut = 0; cut < glb.size(); ++cut) {
    SCOPED_TRACE(".glb cut at " + std::to_string(cut) + " of " + std::to_string(glb.size()));
    gltf_test::write_file(path("cut.glb"), glb.data(), cut);
    expect_error(path("cut.glb"), cut == 0 ? "empty file" : "truncated");
  }
}

// Overwriting any single byte of a .glb either still loads or gives SceneError.
TEST_F(GltfErrors, CorruptedGlbBytesNeverCrash) {
  const std::vector<unsigned char> glb = base_triangle().glb_bytes();
  std::size_t errors = 0, loaded = 0;
  for (std::size_t at = 0; at < glb.size(); ++at)
    for (int value : {0x00, 0xff, int('9'), int('"'), int('-')}) {
      std::vector<unsigned char> bytes = glb;
      bytes[at] = static_cast<unsigned char>(value);
      gltf_test::write_file(path("corrupt.glb"), bytes.data(), bytes.size());
      try {
        (void)read_gltf(path("corrupt.glb"));
        ++loaded;
      } catch (const SceneError&) {
        ++errors;
      }
    }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(loaded, 0u);
}

// COLOR_0 must be RGB or RGBA, of float or normalised unsigned integers, and finite.
TEST_F(GltfErrors, BadVertexColours) {
  {
    GltfBuilder b = base_triangle();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        b.add_vec2(std::vector<glm::vec2>{{1, 0}, {0, 1}, {1, 1}});
    expect_error(b, "COLOR_0 (accessor 2) must be VEC3 or VEC4");
  }
  {
    GltfBuilder b = base_triangle();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        b.add_vec4(std::vector<glm::vec4>{{1, 0, 0, 1}, {0, nan, 0, 1}, {0, 0, 1, 1}});
    expect_error(b, "COLOR_0 holds a non-finite colour component");
  }
  {
    GltfBuilder b = base_triangle();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        b.add_vec3(std::vector<glm::vec3>{{1, 0, 0}, {0, 1, 0}});
    expect_error(b, "COLOR_0 has 2 elements but POSITION has 3");
  }
}

}  // namespace
}  // namespace lancer
