// Builds small glTF files in code for the reader tests: one binary buffer plus the
// JSON document, written as .gltf with a data URI or an external .bin, or as .glb.
// Fixtures live here rather than as checked-in binaries.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/type_precision.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"
#include "temp_dir.h"

namespace lancer::gltf_test {

using nlohmann::json;

inline std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b0 = bytes[i];
    const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
    const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

inline void write_file(const std::filesystem::path& path, const void* data, std::size_t size) {
  // A new file rather than a truncated one: ext4 flushes truncated-and-rewritten
  // files on close, which makes the many-cut-point tests crawl.
  std::error_code ec;
  std::filesystem::remove(path, ec);
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  ASSERT_TRUE(out.good()) << path;
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  write_file(path, text.data(), text.size());
}

inline std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 24-bit bottom-up BMP (stb_image decodes it), pixels given top row first as RGB.
inline std::vector<unsigned char> make_bmp(int width, int height, const std::vector<glm::u8vec3>& rgb) {
  const int row = (width * 3 + 3) / 4 * 4;
  const std::uint32_t size = std::uint32_t(54 + row * height);
  std::vector<unsigned char> out(size, 0);
  auto put32 = [&](std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out[at + std::size_t(k)] = (v >> (8 * k)) & 255;
  };
  out[0] = 'B';
  out[1] = 'M';
  put32(2, size);
  put32(10, 54);
  put32(14, 40);
  put32(18, std::uint32_t(width));
  put32(22, std::uint32_t(height));
  out[26] = 1;   // planes
  out[28] = 24;  // bits per pixel
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::u8vec3 c = rgb[std::size_t((height - 1 - y) * width + x)];
      const std::size_t at = 54 + std::size_t(y * row + x * 3);
      out[at] = c.b;
      out[at + 1] = c.g;
      out[at + 2] = c.r;
    }
  return out;
}

class GltfBuilder {
 public:
  static constexpr int kUByte = 5121, kUShort = 5123, kUInt = 5125, kFloat = 5126;

  std::vector<unsigned char> bin;
  json doc = {{"asset", {{"version", "2.0"}}}};
  // Buffers 1, 2, ... after the one holding `bin` (placeholders without data, say).
  std::vector<json> more_buffers;

  // Appends raw bytes (4-byte aligned) and a bufferView over them; returns its index.
  int add_view(const void* data, std::size_t size, std::size_t stride = 0) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + size);
    if (size) std::memcpy(bin.data() + offset, data, size);
    json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}};
    if (stride) view["byteStride"] = stride;
    return push("bufferViews", view);
  }

  int add_accessor(int view, int component_type, std::size_t count, const char* type, bool normalized = false) {
    json a = {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    return push("accessors", a);
  }

  template <typename Vec>
  int add_floats(const std::vector<Vec>& v, const char* type) {
    return add_accessor(add_view(v.data(), v.size() * sizeof(Vec)), kFloat, v.size(), type);
  }
  int add_vec3(const std::vector<glm::vec3>& v) { return add_floats(v, "VEC3"); }
  int add_vec2(const std::vector<glm::vec2>& v) { return add_floats(v, "VEC2"); }
  int add_vec4(const std::vector<glm::vec4>& v) { return add_floats(v, "VEC4"); }

  template <typename T>
  int add_indices(const std::vector<T>& v) {
    const int type = sizeof(T) == 1 ? kUByte : sizeof(T) == 2 ? kUShort : kUInt;
    return add_accessor(add_view(v.data(), v.size() * sizeof(T)), type, v.size(), "SCALAR");
  }

  // A mesh with one primitive {attributes, mode, [indices], [material]}.
  int add_mesh(json attributes, int mode = 4, int indices = -1, int material = -1) {
    json prim = {{"attributes", std::move(attributes)}, {"mode", mode}};
    if (indices >= 0) prim["indices"] = indices;
    if (material >= 0) prim["material"] = material;
    return push("meshes", {{"primitives", json::array({prim})}});
  }

  int add_node(json node) { return push("nodes", std::move(node)); }
  void set_scene(const std::vector<int>& roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }
  // One node with `mesh` in the default scene.
  void single_node_scene(int mesh) { set_scene({add_node({{"mesh", mesh}})}); }

  int push(const char* key, json value) {
    doc[key].push_back(std::move(value));
    return int(doc[key].size()) - 1;
  }

  // The document with its buffer described by `uri` (omitted when empty).
  std::string json_text(const std::string& uri) const {
    json d = doc;
    if (!bin.empty()) {
      json buffer = {{"byteLength", bin.size()}};
      if (!uri.empty()) buffer["uri"] = uri;
      d["buffers"] = json::array({buffer});
      for (const json& more : more_buffers) d["buffers"].push_back(more);
    }
    return d.dump();
  }

  void write_data_uri_gltf(const std::filesystem::path& path) const {
    write_text(path, json_text("data:application/octet-stream;base64," + base64(bin)));
  }

  void write_external_gltf(const std::filesystem::path& path, const std::string& bin_name) const {
    write_text(path, json_text(bin_name));
    write_file(path.parent_path() / bin_name, bin.data(), bin.size());
  }

  // GLB layout: header (magic, version 2, length), JSON chunk padded with spaces, BIN
  // chunk padded with zeros.
  std::vector<unsigned char> glb_bytes() const {
    std::string text = json_text("");
    while (text.size() % 4 != 0) text += ' ';
    std::vector<unsigned char> payload = bin;
    while (payload.size() % 4 != 0) payload.push_back(0);
    std::vector<unsigned char> out;
    auto put32 = [&](std::uint32_t v) {
      for (int k = 0; k < 4; ++k) out.push_back((v >> (8 * k)) & 255);
    };
    const std::size_t total = 12 + 8 + text.size() + (payload.empty() ? 0 : 8 + payload.size());
    out.reserve(total);
    for (char c : std::string("glTF")) out.push_back(static_cast<unsigned char>(c));
    put32(2);
    put32(std::uint32_t(total));
    put32(std::uint32_t(text.size()));
    put32(0x4E4F534Au);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    if (!payload.empty()) {
      put32(std::uint32_t(payload.size()));
      put32(0x004E4942u);  // "BIN\0"
      out.insert(out.end(), payload.begin(), payload.end());
    }
    return out;
  }
  void write_glb(const std::filesystem::path& path) const {
    const std::vector<unsigned char> bytes = glb_bytes();
    write_file(path, bytes.data(), bytes.size());
  }
};

// A fresh temporary directory per test, removed afterwards.
class GltfTempDir : public ::testing::Test {
 protected:
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

  // read_gltf(file, scene) must throw SceneError whose message has the file name and `word`.
  void expect_error(const std::filesystem::path& file, const std::string& word, int scene = -1) {
    try {
      const Scene s = read_gltf(file, scene);
      ADD_FAILURE() << file << " loaded (" << s.triangle_count() << " triangles), expected an error with '" << word
                    << "'";
    } catch (const SceneError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << "expected '" << word << "' in: " << msg;
    }
  }
  // read_gltf(file), which must not warn that an extension is unsupported (the extension
  // under test was read, not skipped).
  Scene read_supported(const std::filesystem::path& file) {
    SceneWarningLog log;
    Scene s = read_gltf(file);
    for (const std::string& w : log.take()) EXPECT_EQ(w.find("not supported"), std::string::npos) << w;
    return s;
  }
  // The same for `b` written as bad.gltf.
  void expect_error(const GltfBuilder& b, const std::string& word) {
    b.write_data_uri_gltf(path("bad.gltf"));
    expect_error(path("bad.gltf"), word);
  }

  test::TempDir temp_{"lancer_gltf"};
  const std::filesystem::path& dir_ = temp_.path();
};

// Makes animation 0 a single channel moving `path` ("translation", "rotation", "scale",
// "weights") of node `node`; `values` are the sampler's output floats, `type` their
// accessor type. Replaces any animation the file had.
inline void animate(GltfBuilder& b, int node, const char* path, const std::vector<float>& times,
                    const std::vector<float>& values, const char* type, const char* interpolation) {
  const int input = b.add_floats(std::vector<glm::vec<1, float>>(times.begin(), times.end()), "SCALAR");
  const int width = std::string(type) == "VEC4" ? 4 : std::string(type) == "VEC3" ? 3 : 1;
  const int output = b.add_accessor(b.add_view(values.data(), values.size() * sizeof(float)), GltfBuilder::kFloat,
                                    values.size() / std::size_t(width), type);
  b.doc["animations"] = json::array(
      {{{"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}},
        {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}}}});
}

// One CCW triangle in the z = 0 plane facing +z.
inline std::vector<glm::vec3> unit_triangle() { return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}; }

}  // namespace lancer::gltf_test
