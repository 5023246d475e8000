// Every prefix of a valid scene file, as a crashed download or a full disk leaves it:
// load_scene must either throw SceneError naming the file or return a valid scene, and
// never crash, hang or throw anything else. Files: the committed Cornell box (.gltf with
// its buffer in a data URI; sampled, see below), a textured .glb built here, and an OBJ
// with its MTL (each of the two cut in turn) at every cut point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "gltf_test_files.h"
#include "scene/load_scene.h"
#include "scene/scene_error.h"
#include "test_paths.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What a truncated file may legitimately load as: well-formed arrays, finite corners,
// material ids in range, and no more triangles than the whole file has.
void expect_valid_scene(const Scene& scene, std::size_t max_triangles, const std::string& where) {
  const std::size_t n = scene.triangle_count();
  EXPECT_LE(n, max_triangles) << where;
  ASSERT_EQ(scene.material_id.size(), n) << where;
  ASSERT_EQ(scene.source_triangle_id.size(), n) << where;
  ASSERT_EQ(scene.attrib_flags.size(), n) << where;
  // A per-corner array is empty when no triangle has the attribute, else one entry per corner.
  bool any_normals = false, any_texcoords = false;
  for (std::uint8_t f : scene.attrib_flags) {
    any_normals = any_normals || (f & kHasNormals);
    any_texcoords = any_texcoords || (f & kHasTexcoords);
  }
  ASSERT_TRUE(scene.normals.empty() || scene.normals.size() == 3 * n) << where;
  ASSERT_TRUE(scene.texcoords.empty() || scene.texcoords.size() == 3 * n) << where;
  if (any_normals) {
    ASSERT_EQ(scene.normals.size(), 3 * n) << where;
  }
  if (any_texcoords) {
    ASSERT_EQ(scene.texcoords.size(), 3 * n) << where;
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(finite(scene.triangles.vertex(i, k))) << where << ", triangle " << i;
    ASSERT_LT(scene.material_id[i], scene.materials.size()) << where << ", triangle " << i;
  }
}

struct CutCounts {
  std::size_t errors = 0;
  std::size_t loaded = 0;
};

// Every cut length 0..size-1.
std::vector<std::size_t> every_cut(std::size_t size) {
  std::vector<std::size_t> cuts(size);
  for (std::size_t i = 0; i < size; ++i) cuts[i] = i;
  return cuts;
}

// For larger files: every cut in the first and last `end_bytes`, where the containers
// open and close, and `samples` evenly spaced cuts in between.
std::vector<std::size_t> ends_and_samples(std::size_t size, std::size_t end_bytes, std::size_t samples) {
  if (size <= 2 * end_bytes + samples) return every_cut(size);
  std::vector<std::size_t> cuts;
  for (std::size_t i = 0; i < end_bytes; ++i) cuts.push_back(i);
  const std::size_t middle = size - 2 * end_bytes;
  for (std::size_t k = 0; k < samples; ++k) cuts.push_back(end_bytes + (2 * k + 1) * middle / (2 * samples));
  for (std::size_t i = size - end_bytes; i < size; ++i) cuts.push_back(i);
  return cuts;
}

// For each cut length: write(cut) puts that prefix at `path`, then load_scene reads it.
CutCounts load_every_prefix(const std::filesystem::path& path, const std::vector<std::size_t>& cuts,
                            std::size_t size, std::size_t max_triangles, const std::function<void(std::size_t)>& write) {
  CutCounts counts;
  for (const std::size_t cut : cuts) {
    const std::string where = path.filename().string() + " cut at " + std::to_string(cut) + " of " +
                              std::to_string(size);
    write(cut);
    testing::internal::CaptureStderr();  // warnings about the odd partial file are expected
    try {
      const Scene scene = load_scene(path);
      ++counts.loaded;
      expect_valid_scene(scene, max_triangles, where);
    } catch (const SceneError& e) {
      ++counts.errors;
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << where << ": " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << where << ": threw something other than SceneError: " << e.what();
    } catch (...) {
      ADD_FAILURE() << where << ": threw a non-std exception";
    }
    testing::internal::GetCapturedStderr();
  }
  return counts;
}

CutCounts load_every_prefix(const std::filesystem::path& path, std::size_t size, std::size_t max_triangles,
                            const std::function<void(std::size_t)>& write) {
  return load_every_prefix(path, every_cut(size), size, max_triangles, write);
}

CutCounts load_every_prefix(const std::filesystem::path& path, const std::string& content,
                            std::size_t max_triangles) {
  return load_every_prefix(path, content.size(), max_triangles,
                           [&](std::size_t cut) { gltf_test::write_file(path, content.data(), cut); });
}

class Truncation : public gltf_test::GltfTempDir {};

// The Cornell box is 14 KB: every cut in its first and last 4 KiB (the document's
// opening, and the end of the data URI with the closing brackets), 300 in between.
TEST_F(Truncation, CornellBoxGltfPrefixes) {
  const std::filesystem::path source = test::scenes_dir() / "cornell-box.gltf";
  const std::vector<unsigned char> bytes = gltf_test::read_bytes(source);
  ASSERT_GT(bytes.size(), 10000u) << source;
  const std::size_t full = load_scene(source).triangle_count();
  const std::filesystem::path cut_path = path("cornell-box.gltf");
  const std::vector<std::size_t> cuts = ends_and_samples(bytes.size(), 4096, 300);
  const CutCounts counts = load_every_prefix(cut_path, cuts, bytes.size(), full, [&](std::size_t cut) {
    gltf_test::write_file(cut_path, bytes.data(), cut);
  });
  EXPECT_EQ(counts.loaded + counts.errors, cuts.size());
  // Only a cut in the trailing whitespace (if any) leaves a complete JSON document.
  EXPECT_LE(counts.loaded, 2u);
}

// A quad with normals, texcoords, a textured material (the BMP in the BIN chunk) and a
// camera: more of the reader than a bare triangle.
GltfBuilder textured_quad() {
  GltfBuilder b;
  const int positions = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int normals = b.add_vec3({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int uvs = b.add_vec2({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const int indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  const std::vector<unsigned char> bmp = gltf_test::make_bmp(2, 1, {{255, 0, 0}, {0, 255, 0}});
  b.push("images", {{"bufferView", b.add_view(bmp.data(), bmp.size())}, {"mimeType", "image/bmp"}});
  b.push("textures", {{"source", 0}});
  b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}}});
  const int mesh = b.add_mesh({{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}, 4, indices, 0);
  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}});
  b.set_scene({b.add_node({{"mesh", mesh}}), b.add_node({{"camera", 0}, {"translation", {0.5, 0.5, 2.0}}})});
  return b;
}

TEST_F(Truncation, TexturedGlbEveryPrefix) {
  const std::vector<unsigned char> glb = textured_quad().glb_bytes();
  gltf_test::write_file(path("whole.glb"), glb.data(), glb.size());
  ASSERT_EQ(load_scene(path("whole.glb")).triangle_count(), 2u);
  const std::filesystem::path cut_path = path("cut.glb");
  const CutCounts counts = load_every_prefix(cut_path, glb.size(), 2, [&](std::size_t cut) {
    gltf_test::write_file(cut_path, glb.data(), cut);
  });
  // The header states the file's length, so every strict prefix is refused.
  EXPECT_EQ(counts.loaded, 0u);
}

// A truncated BIN chunk whose header and chunk lengths were rewritten to match (a writer
// that lost the end of its data): the buffer then holds less than the accessors need.
TEST_F(Truncation, GlbWithShortenedBinChunkEveryLength) {
  const std::vector<unsigned char> glb = textured_quad().glb_bytes();
  auto get32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | glb[at + std::size_t(k)];
    return v;
  };
  const std::size_t bin_chunk = 20 + get32(12);  // the BIN chunk's header follows the JSON
  const std::size_t bin_data = bin_chunk + 8;
  ASSERT_EQ(bin_data + get32(bin_chunk), glb.size());
  const std::filesystem::path cut_path = path("short-bin.glb");
  const CutCounts counts = load_every_prefix(cut_path, glb.size() - bin_data, 2, [&](std::size_t length) {
    std::vector<unsigned char> bytes(glb.begin(), glb.begin() + std::ptrdiff_t(bin_data + length));
    auto put32 = [&](std::size_t at, std::size_t v) {
      for (int k = 0; k < 4; ++k) bytes[at + std::size_t(k)] = static_cast<unsigned char>((v >> (8 * k)) & 255);
    };
    put32(8, bytes.size());
    put32(bin_chunk, length);
    gltf_test::write_file(cut_path, bytes.data(), bytes.size());
  });
  // The buffer's byteLength no longer matches: every length short of the whole is refused.
  EXPECT_EQ(counts.loaded, 0u);
}

const std::string kObj =
    "# truncation test: two materials, attributes, a polygon and relative indices\n"
    "mtllib cut.mtl\no box\n"
    "v 0 0 0\nv 1.5 0 0\nv 1.5 1.25 0\nv 0 1.25 0\nv 0.75 2 -1\nv 0.25 0.5 -2.5\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvn 0 0.6 0.8\n"
    "usemtl red\nf 1/1/1 2/2/1 3/3/1 4/4/1\ns off\ng lid\n"
    "usemtl glass\nf -3/-1/-1 -4/-2/-2 6/1/2\nf 1 3 5 6\nl 1 2\n";
const std::string kMtl =
    "# two materials\nnewmtl red\nKa 0 0 0\nKd 0.8 0.1 0.1\nKs 0.04 0.04 0.04\nNs 32\nillum 2\n"
    "newmtl glass\nKd 0 0 0\nKs 1 1 1\nNi 1.5\nTf 0.9 0.9 0.9\nd 0.25\nillum 7\nKe 0.1 0.2 0.3\n";

TEST_F(Truncation, ObjEveryPrefixWithWholeMtl) {
  gltf_test::write_text(path("cut.mtl"), kMtl);
  gltf_test::write_text(path("whole.obj"), kObj);
  const std::size_t full = load_scene(path("whole.obj")).triangle_count();
  ASSERT_EQ(full, 5u);
  const CutCounts counts = load_every_prefix(path("cut.obj"), kObj, full);
  // Cuts between complete statements leave a valid, smaller OBJ.
  EXPECT_GT(counts.loaded, 0u);
  EXPECT_GT(counts.errors, 0u);
}

TEST_F(Truncation, MtlEveryPrefixWithWholeObj) {
  gltf_test::write_text(path("cut.obj"), kObj);
  const std::filesystem::path mtl = path("cut.mtl");
  const CutCounts counts = load_every_prefix(path("cut.obj"), kMtl.size(), 5, [&](std::size_t cut) {
    gltf_test::write_file(mtl, kMtl.data(), cut);
  });
  // A partial MTL loses or shortens materials; the OBJ falls back to a default one.
  EXPECT_GT(counts.loaded, 0u);
}

}  // namespace
}  // namespace lancer
