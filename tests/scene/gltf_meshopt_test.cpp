// EXT_meshopt_compression: a compressed copy of a mesh, encoded here with meshoptimizer's
// own encoder and filters (as gltfpack writes it: quantized attributes, a fallback buffer
// without data), loads to the same triangles as an uncompressed copy holding the bytes the
// codec decodes to, as .gltf and as .glb. Data that does not decode, the spec's rules
// broken and hostile sizes are refused naming the file and the extension, before any
// allocation of the claimed size.
#include <meshoptimizer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using Bytes = std::vector<unsigned char>;

constexpr const char* kExt = "EXT_meshopt_compression";
constexpr int kByte = 5120, kShort = 5122;

struct Mesh {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> indices;
};

// A bumpy sphere of 16 x 8 quads, open at the poles (no degenerate triangles), with its
// normals of the unbumped sphere and UVs.
Mesh bumpy_sphere() {
  Mesh m;
  constexpr int kSlices = 16, kStacks = 8;
  for (int j = 0; j <= kStacks; ++j)
    for (int i = 0; i <= kSlices; ++i) {
      const float theta = 0.3f + 2.5f * float(j) / kStacks, phi = 6.2831853f * float(i) / kSlices;
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      m.positions.push_back(d * (1.0f + 0.1f * std::sin(3.0f * phi)));
      m.normals.push_back(d);
      m.uvs.emplace_back(float(i) / kSlices, float(j) / kStacks);
    }
  for (int j = 0; j < kStacks; ++j)
    for (int i = 0; i < kSlices; ++i) {
      const std::uint32_t a = std::uint32_t(j * (kSlices + 1) + i), b = a + 1, c = a + kSlices + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
    }
  // The TRIANGLES codec may start a triangle at another corner (same winding): take the
  // order it gives back, so that every copy of the file lists the same corners.
  Bytes encoded(meshopt_encodeIndexBufferBound(m.indices.size(), m.positions.size()));
  encoded.resize(meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), m.indices.data(), m.indices.size()));
  EXPECT_EQ(meshopt_decodeIndexBuffer(m.indices.data(), m.indices.size(), 4, encoded.data(), encoded.size()), 0);
  return m;
}

// One bufferView's data: as an uncompressed file stores it (what decoding and the filter
// give) and as the extension stores it.
struct Stream {
  Bytes plain, encoded;
  std::size_t count = 0, stride = 0;
  std::string mode = "ATTRIBUTES", filter = "NONE";
};

// Vertex data, filtered beforehand when `filter` is not NONE (`filtered` holds the
// encoder's output); `plain` is what the library's own filter decoder makes of it.
Stream vertex_stream(const void* data, std::size_t count, std::size_t stride, const std::string& filter = "NONE") {
  Stream s;
  s.count = count;
  s.stride = stride;
  s.filter = filter;
  const auto* bytes = static_cast<const unsigned char*>(data);
  s.plain.assign(bytes, bytes + count * stride);
  s.encoded.resize(meshopt_encodeVertexBufferBound(count, stride));
  s.encoded.resize(meshopt_encodeVertexBuffer(s.encoded.data(), s.encoded.size(), data, count, stride));
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(s.plain.data(), count, stride);
  if (filter == "QUATERNION") meshopt_decodeFilterQuat(s.plain.data(), count, stride);
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(s.plain.data(), count, stride);
  return s;
}

// Indices as TRIANGLES (meshopt_encodeIndexBuffer) or INDICES (meshopt_encodeIndexSequence),
// stored with `stride` bytes each.
Stream index_stream(const std::vector<std::uint32_t>& indices, std::size_t stride, const std::string& mode) {
  Stream s;
  s.count = indices.size();
  s.stride = stride;
  s.mode = mode;
  for (std::uint32_t i : indices)
    for (std::size_t k = 0; k < stride; ++k) s.plain.push_back(static_cast<unsigned char>(i >> (8 * k)));
  std::uint32_t vertices = 0;
  for (std::uint32_t i : indices) vertices = std::max(vertices, i + 1);
  if (mode == "TRIANGLES") {
    s.encoded.resize(meshopt_encodeIndexBufferBound(indices.size(), vertices));
    s.encoded.resize(meshopt_encodeIndexBuffer(s.encoded.data(), s.encoded.size(), indices.data(), indices.size()));
  } else {
    s.encoded.resize(meshopt_encodeIndexSequenceBound(indices.size(), vertices));
    s.encoded.resize(meshopt_encodeIndexSequence(s.encoded.data(), s.encoded.size(), indices.data(), indices.size()));
  }
  return s;
}

// Appends `s` to `b`: uncompressed, a bufferView over s.plain; compressed, s.encoded in
// buffer 0 and a bufferView on the placeholder buffer 1 whose extension points at it.
int add_stream(GltfBuilder& b, const Stream& s, bool compressed, bool vertex_stride) {
  if (!compressed) return b.add_view(s.plain.data(), s.plain.size(), vertex_stride ? s.stride : 0);
  if (b.more_buffers.empty())
    b.more_buffers.push_back({{"byteLength", 0}, {"extensions", {{kExt, {{"fallback", true}}}}}});
  json& fallback = b.more_buffers[0];
  while (b.bin.size() % 4 != 0) b.bin.push_back(0);
  json ext = {{"buffer", 0},
              {"byteOffset", b.bin.size()},
              {"byteLength", s.encoded.size()},
              {"byteStride", s.stride},
              {"count", s.count},
              {"mode", s.mode}};
  if (s.filter != "NONE") ext["filter"] = s.filter;
  b.bin.insert(b.bin.end(), s.encoded.begin(), s.encoded.end());
  const std::size_t at = (fallback["byteLength"].get<std::size_t>() + 3) / 4 * 4;
  fallback["byteLength"] = at + s.plain.size();
  json view = {{"buffer", 1}, {"byteOffset", at}, {"byteLength", s.plain.size()}, {"extensions", {{kExt, ext}}}};
  if (vertex_stride) view["byteStride"] = s.stride;
  return b.push("bufferViews", view);
}

void declare(GltfBuilder& b, const std::vector<std::string>& required, const std::vector<std::string>& used = {}) {
  b.doc["extensionsRequired"] = required;
  b.doc["extensionsUsed"] = required;
  for (const std::string& u : used) b.doc["extensionsUsed"].push_back(u);
}

// The sphere as gltfpack writes it: FLOAT positions, 8-bit octahedral normals (normalized
// BYTE, KHR_mesh_quantization), texture coordinates through the exponential filter, 16-bit
// indices; compressed or not. `index_mode` TRIANGLES or INDICES.
GltfBuilder sphere_file(const Mesh& m, bool compressed, const std::string& index_mode = "TRIANGLES") {
  GltfBuilder b;
  std::vector<float> normal4, uv2;
  for (const glm::vec3& n : m.normals) normal4.insert(normal4.end(), {n.x, n.y, n.z, 0.0f});
  for (const glm::vec2& t : m.uvs) uv2.insert(uv2.end(), {t.x, t.y});
  const std::size_t n = m.positions.size();
  Bytes oct(n * 4), exp(n * 8);
  meshopt_encodeFilterOct(oct.data(), n, 4, 8, normal4.data());
  meshopt_encodeFilterExp(exp.data(), n, 8, 15, uv2.data());
  const int pos = b.add_accessor(add_stream(b, vertex_stream(m.positions.data(), n, 12), compressed, true),
                                 GltfBuilder::kFloat, n, "VEC3");
  const int nrm = b.add_accessor(add_stream(b, vertex_stream(oct.data(), n, 4, "OCTAHEDRAL"), compressed, true), kByte,
                                 n, "VEC3", true);
  const int uv = b.add_accessor(add_stream(b, vertex_stream(exp.data(), n, 8, "EXPONENTIAL"), compressed, true),
                                GltfBuilder::kFloat, n, "VEC2");
  const int idx = b.add_accessor(add_stream(b, index_stream(m.indices, 2, index_mode), compressed, false),
                                 GltfBuilder::kUShort, m.indices.size(), "SCALAR");
  b.single_node_scene(b.add_mesh({{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}, 4, idx));
  if (compressed) {
    declare(b, {"KHR_mesh_quantization", kExt});
  } else {
    declare(b, {"KHR_mesh_quantization"});
  }
  return b;
}

void expect_same_triangles(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.triangle_count(), b.triangle_count());
  ASSERT_EQ(a.normals.size(), b.normals.size());
  ASSERT_EQ(a.texcoords.size(), b.texcoords.size());
  for (std::size_t t = 0; t < a.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = 3 * t + std::size_t(k);
      ASSERT_TRUE(a.triangles.vertex(t, k) == b.triangles.vertex(t, k)) << "triangle " << t << " corner " << k;
      ASSERT_TRUE(a.normals[c] == b.normals[c]) << "corner " << c;
      ASSERT_TRUE(a.texcoords[c] == b.texcoords[c]) << "corner " << c;
    }
}

// The decoded scene is the sphere itself: positions exact, normals and UVs as close as
// 8-bit octahedral and 15-bit exponential encoding allow (so the filters were applied).
void expect_sphere(const Scene& s, const Mesh& m) {
  ASSERT_EQ(s.triangle_count(), m.indices.size() / 3);
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.indices[3 * std::size_t(s.source_triangle_id[t]) + std::size_t(k)];
      const std::size_t c = 3 * t + std::size_t(k);
      ASSERT_TRUE(s.triangles.vertex(t, k) == m.positions[v]) << "triangle " << t;
      ASSERT_LT(glm::length(s.normals[c] - m.normals[v]), 0.02f) << "corner " << c;
      ASSERT_LT(glm::length(s.texcoords[c] - m.uvs[v]), 1e-4f) << "corner " << c;
    }
}

class GltfMeshopt : public gltf_test::GltfTempDir {
 protected:
  // `b`, written as bad.glb, must be refused naming the file, the extension and `word`.
  void expect_meshopt_error(const GltfBuilder& b, const std::string& word) {
    b.write_glb(path("bad.glb"));
    expect_error(path("bad.glb"), word);
    expect_error(path("bad.glb"), kExt);
  }
};

TEST_F(GltfMeshopt, CompressedCopyLoadsTheSameTriangles) {
  const Mesh m = bumpy_sphere();
  sphere_file(m, false).write_data_uri_gltf(path("plain.gltf"));
  const GltfBuilder packed = sphere_file(m, true);
  packed.write_data_uri_gltf(path("packed.gltf"));
  ASSERT_FALSE(packed.more_buffers.at(0).contains("uri")) << "the fallback buffer has no data";
  const Scene reference = read_supported(path("plain.gltf"));
  const Scene decoded = read_supported(path("packed.gltf"));
  expect_same_triangles(decoded, reference);
  expect_sphere(decoded, m);
}

// In a .glb tinygltf takes a buffer without uri for the BIN chunk and refuses it when its
// byteLength (the uncompressed size) exceeds the chunk's.
TEST_F(GltfMeshopt, GlbWithAFallbackBufferWithoutData) {
  const Mesh m = bumpy_sphere();
  sphere_file(m, false).write_data_uri_gltf(path("plain.gltf"));
  const GltfBuilder packed = sphere_file(m, true);
  ASSERT_GT(packed.more_buffers.at(0)["byteLength"].get<std::size_t>(), packed.bin.size());
  packed.write_glb(path("packed.glb"));
  expect_same_triangles(read_supported(path("packed.glb")), read_supported(path("plain.gltf")));
}

// The spec's own example of a placeholder, {"byteLength": N} without the fallback tag, and
// a tagged one whose uri names a file that does not exist: neither is read.
TEST_F(GltfMeshopt, PlaceholderBuffersAreNeverRead) {
  const Mesh m = bumpy_sphere();
  sphere_file(m, false).write_data_uri_gltf(path("plain.gltf"));
  const Scene reference = read_supported(path("plain.gltf"));
  GltfBuilder untagged = sphere_file(m, true);
  untagged.more_buffers[0].erase("extensions");
  untagged.write_data_uri_gltf(path("untagged.gltf"));
  expect_same_triangles(read_supported(path("untagged.gltf")), reference);
  untagged.write_glb(path("untagged.glb"));
  expect_same_triangles(read_supported(path("untagged.glb")), reference);
  GltfBuilder missing = sphere_file(m, true);
  missing.more_buffers[0]["uri"] = "missing.fallback.bin";
  missing.doc["extensionsRequired"] = {"KHR_mesh_quantization"};  // used only: a fallback exists, in principle
  missing.write_data_uri_gltf(path("missing.gltf"));
  expect_same_triangles(read_supported(path("missing.gltf")), reference);
}

// INDICES mode with 32-bit indices, and the QUATERNION filter on EXT_mesh_gpu_instancing
// rotations (16-bit normalized, as gltfpack stores them).
TEST_F(GltfMeshopt, IndexSequencesAndQuaternions) {
  const Mesh m = bumpy_sphere();
  const std::vector<float> quats = {0, 0, 0, 1, 0, 0.70710678f, 0, 0.70710678f, 0.5f, 0.5f, 0.5f, 0.5f};
  Bytes packed_quats(3 * 8);
  meshopt_encodeFilterQuat(packed_quats.data(), 3, 8, 12, quats.data());
  const std::vector<glm::vec3> offsets = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
  Scene scenes[2];
  for (const bool compressed : {false, true}) {
    GltfBuilder b = sphere_file(m, compressed, "INDICES");
    json& indices = b.doc["accessors"][3];
    indices["componentType"] = GltfBuilder::kUInt;
    const Stream wide = index_stream(m.indices, 4, "INDICES");
    indices["bufferView"] = add_stream(b, wide, compressed, false);
    const int rot =
        b.add_accessor(add_stream(b, vertex_stream(packed_quats.data(), 3, 8, "QUATERNION"), compressed, true), kShort,
                       3, "VEC4", true);
    const int move = b.add_vec3(offsets);
    b.doc["nodes"][0]["extensions"] = {
        {"EXT_mesh_gpu_instancing", {{"attributes", {{"ROTATION", rot}, {"TRANSLATION", move}}}}}};
    b.doc["extensionsUsed"].push_back("EXT_mesh_gpu_instancing");
    const std::string name = compressed ? "packed.gltf" : "plain.gltf";
    b.write_data_uri_gltf(path(name));
    scenes[compressed ? 1 : 0] = read_supported(path(name));
  }
  const std::size_t per = m.indices.size() / 3;
  ASSERT_EQ(scenes[1].triangle_count(), 3 * per);
  expect_same_triangles(scenes[1], scenes[0]);
  // The second instance is the first (unturned) turned 90 degrees about +y: the decoded
  // quaternion is that turn, to 12 bits.
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 p = scenes[1].triangles.vertex(0, k);
    EXPECT_LT(glm::length(scenes[1].triangles.vertex(per, k) - (glm::vec3(p.z, p.y, -p.x) + offsets[1])), 5e-3f);
  }
}

TEST_F(GltfMeshopt, DataThatDoesNotDecodeIsRefused) {
  const Mesh m = bumpy_sphere();
  GltfBuilder header = sphere_file(m, true);
  header.bin[header.doc["bufferViews"][0]["extensions"][kExt]["byteOffset"].get<std::size_t>()] = 0x13;
  expect_meshopt_error(header, "unknown header");
  GltfBuilder cut = sphere_file(m, true);
  cut.doc["bufferViews"][1]["extensions"][kExt]["byteLength"] =
      cut.doc["bufferViews"][1]["extensions"][kExt]["byteLength"].get<std::size_t>() - 9;
  expect_meshopt_error(cut, "the data ends early or is corrupt");
  GltfBuilder cut_indices = sphere_file(m, true);
  cut_indices.doc["bufferViews"][3]["extensions"][kExt]["byteLength"] = 300;
  expect_meshopt_error(cut_indices, "does not decode");
}

// Flipped bytes anywhere in the compressed data give a scene or a SceneError (the decoders
// may make garbage of damaged data, which the accessor checks then meet), never a crash.
TEST_F(GltfMeshopt, DamagedDataNeverCrashes) {
  const GltfBuilder intact = sphere_file(bumpy_sphere(), true);
  int refused = 0;
  for (std::size_t seed = 1; seed <= 40; ++seed) {
    GltfBuilder b = intact;
    for (std::size_t k = seed * 7 % 13; k < b.bin.size(); k += 11 + seed)
      b.bin[k] ^= static_cast<unsigned char>(seed * 37);
    b.write_glb(path("damaged.glb"));
    testing::internal::CaptureStderr();
    try {
      (void)read_gltf(path("damaged.glb"));
    } catch (const SceneError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("damaged.glb"), std::string::npos) << e.what();
    }
    testing::internal::GetCapturedStderr();
  }
  EXPECT_GT(refused, 0);
}

// A count the compressed bytes cannot hold is refused before the decoded size is
// allocated (4 TiB here: an allocation would throw std::bad_alloc, not SceneError).
TEST_F(GltfMeshopt, HugeCountsAreRefusedBeforeAllocating) {
  const std::size_t huge = std::size_t(1) << 40;
  GltfBuilder b = sphere_file(bumpy_sphere(), true);
  b.doc["bufferViews"][0]["extensions"][kExt]["count"] = huge;
  b.doc["bufferViews"][0]["byteLength"] = huge * 12;
  b.more_buffers[0]["byteLength"] = huge * 16;
  expect_meshopt_error(b, "cannot hold 1099511627776 elements of 12 bytes");
  // count * byteStride wraps around 64 bits.
  b.doc["bufferViews"][0]["extensions"][kExt]["count"] = (std::size_t(1) << 62) + 1;
  b.doc["bufferViews"][0]["byteLength"] = 12;
  expect_meshopt_error(b, "is not the bufferView's byteLength");
  GltfBuilder outside = sphere_file(bumpy_sphere(), true);
  outside.doc["bufferViews"][2]["extensions"][kExt]["byteOffset"] = std::size_t(1) << 60;
  expect_meshopt_error(outside, "runs past the end of buffer 0");
}

// Views that each decode to 64 MiB from one shared 1 MiB range: 65 of them pass the
// 4 GiB limit, which is checked for the whole file before any view is decoded.
TEST_F(GltfMeshopt, DecodedSizeIsLimitedPerFile) {
  GltfBuilder b;
  b.bin.assign(std::size_t(1) << 20, 0);
  b.more_buffers.push_back({{"byteLength", 65ull << 26}, {"extensions", {{kExt, {{"fallback", true}}}}}});
  for (std::size_t i = 0; i < 65; ++i)
    b.push("bufferViews", {{"buffer", 1},
                           {"byteOffset", i << 26},
                           {"byteLength", std::size_t(1) << 26},
                           {"extensions",
                            {{kExt,
                              {{"buffer", 0},
                               {"byteLength", b.bin.size()},
                               {"byteStride", 4},
                               {"count", std::size_t(1) << 24},
                               {"mode", "ATTRIBUTES"}}}}}});
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3(gltf_test::unit_triangle())}}));
  declare(b, {kExt});
  expect_meshopt_error(b,
                       "bufferView 64 EXT_meshopt_compression: the file's compressed bufferViews decode to more than "
                       "the limit of 4294967296 bytes");
}

// The spec's rules for a valid extension object, each with its message.
TEST_F(GltfMeshopt, MalformedExtensionsAreRefused) {
  const Mesh m = bumpy_sphere();
  auto with = [&](int view, const char* key, const json& value) {
    GltfBuilder b = sphere_file(m, true);
    if (value.is_null()) {
      b.doc["bufferViews"][view]["extensions"][kExt].erase(key);
    } else {
      b.doc["bufferViews"][view]["extensions"][kExt][key] = value;
    }
    return b;
  };
  expect_meshopt_error(with(0, "mode", "LINES"), "unknown mode 'LINES'");
  expect_meshopt_error(with(0, "filter", "ROT"), "unknown filter 'ROT'");
  expect_meshopt_error(with(3, "filter", "OCTAHEDRAL"), "index modes take no filter");
  expect_meshopt_error(with(0, "count", nullptr), "needs 'count'");
  expect_meshopt_error(with(0, "buffer", 7), "buffer index 7 out of range");
  expect_meshopt_error(with(3, "count", m.indices.size() - 1), "not a multiple of 3");
  expect_meshopt_error(with(3, "byteStride", 1), "must be 2 or 4");
  expect_meshopt_error(with(1, "filter", "QUATERNION"), "must be 8 for filter QUATERNION");
  GltfBuilder odd = with(0, "byteStride", 6);
  odd.doc["bufferViews"][0]["byteStride"] = 6;
  expect_meshopt_error(odd, "must be a multiple of 4 up to 256");
  GltfBuilder differ = sphere_file(m, true);
  differ.doc["bufferViews"][0]["byteStride"] = 16;
  expect_meshopt_error(differ, "differs from the bufferView's byteStride 16");
  GltfBuilder typed = with(0, "count", "12");
  typed.write_glb(path("typed.glb"));
  expect_error(path("typed.glb"), "wrong JSON type: bufferViews[0].extensions.EXT_meshopt_compression.count");
}

}  // namespace
}  // namespace lancer
