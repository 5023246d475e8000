// Shared by the libFuzzer targets: a scratch folder for readers that take a path, a way
// to mute the readers' warnings, and the checks every successfully loaded scene must
// pass. A failed check aborts, which libFuzzer reports as a crash with the input saved:
// a reader that returns a broken scene is as much a finding as one that crashes.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <streambuf>
#include <string>
#include <string_view>

#include <glm/geometric.hpp>

#include "scene/scene.h"

namespace lancer::fuzz {

[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

inline void require(bool ok, const std::string& what) {
  if (!ok) fail(what);
}

// The readers warn on std::cerr for every odd input; at thousands of runs a second that
// drowns libFuzzer's own output. Sanitizer reports go to fd 2 directly and stay visible.
inline void mute_std_cerr() {
  struct Discard final : std::streambuf {
    int overflow(int c) override { return traits_type::not_eof(c); }
  };
  static Discard discard;
  std::cerr.rdbuf(&discard);
}

// Replaces `path` with exactly `bytes` (a new file each time rather than a truncated one).
inline void write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  require(out.good(), "cannot write the scratch file " + path.string());
}

// A 1x1 RGB PNG, so inputs naming "texture.png" (as the seed corpora do) reach the
// image decoding paths of both readers.
inline constexpr unsigned char kTexturePng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00,
    0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xdf, 0xc0, 0x00, 0x00, 0x04, 0x01, 0x01, 0x80, 0xc5,
    0x2a, 0x18, 0x5d, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

// A folder of this process's own under $TMPDIR (one per fuzzing job, so parallel jobs
// never share files), holding texture.png. libFuzzer leaves with _Exit, so nothing here
// removes it: run_fuzzers.sh points TMPDIR at a folder it deletes afterwards.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("lancer_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    write_file(d / "texture.png", std::string_view(reinterpret_cast<const char*>(kTexturePng), sizeof kTexturePng));
    return d;
  }();
  return dir;
}

inline bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }

inline void check_texture_ref(const Scene& scene, const TextureRef& ref, const std::string& what) {
  require(ref.texture >= -1 && (ref.texture < 0 || std::size_t(ref.texture) < scene.textures.size()),
          what + ": texture index out of range");
  require(ref.texcoord == 0 || ref.texcoord == 1, what + ": texcoord set other than 0 or 1");
  require(std::isfinite(ref.scale), what + ": non-finite scale");
  for (int col = 0; col < 3; ++col) require(finite(ref.transform[col]), what + ": non-finite texture transform");
}

// What scene.h promises of a loaded scene: aligned per-triangle and per-corner arrays,
// finite world-space positions, unit or zero normals, every index in range, and decoded
// images whose pixel count matches their size.
inline void check_scene(const Scene& scene) {
  const std::size_t n = scene.triangle_count();
  for (int k = 0; k < 3; ++k)
    require(scene.triangles.x[k].size() == n && scene.triangles.y[k].size() == n && scene.triangles.z[k].size() == n,
            "triangle SoA arrays of different lengths");
  require(scene.material_id.size() == n && scene.source_triangle_id.size() == n && scene.attrib_flags.size() == n,
          "per-triangle arrays do not match the triangle count");
  // Each per-corner array is empty exactly when no triangle has its attribute.
  const auto check_corners = [&](std::size_t size, std::uint8_t bit, const char* what) {
    bool any = false;
    for (std::uint8_t flags : scene.attrib_flags) any = any || (flags & bit) != 0;
    require(size == (any ? 3 * n : 0), std::string(what) + (any ? ": some triangle has it but the array is not 3x the triangle count"
                                                               : ": no triangle has it but the array is not empty"));
  };
  check_corners(scene.normals.size(), kHasNormals, "normals");
  check_corners(scene.texcoords.size(), kHasTexcoords, "texcoords");
  check_corners(scene.tangents.size(), kHasTangents, "tangents");
  check_corners(scene.texcoords1.size(), kHasTexcoords1, "TEXCOORD_1");
  check_corners(scene.colors.size(), kHasColors, "COLOR_0");
  for (const glm::vec4& c : scene.colors)
    require(c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f && c.a >= 0.0f && c.r <= 1.0f && c.g <= 1.0f && c.b <= 1.0f &&
                c.a <= 1.0f,
            "a COLOR_0 value outside [0, 1]");
  require(!scene.materials.empty(), "a loaded scene has no material");
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) require(finite(scene.triangles.vertex(i, k)), "non-finite vertex position");
    require(scene.material_id[i] < scene.materials.size(), "material id out of range");
  }
  for (std::size_t c = 0; c < scene.normals.size(); ++c) {
    const float len = glm::length(scene.normals[c]);
    require(len == 0.0f || std::fabs(len - 1.0f) < 1e-3f, "a corner normal is neither unit length nor zero");
  }
  for (const Material& m : scene.materials) {
    require(finite(m.base_color) && std::isfinite(m.metallic) && std::isfinite(m.roughness) &&
                finite(m.emission()) && std::isfinite(m.alpha_cutoff) && std::isfinite(m.ior) &&
                std::isfinite(m.transmission) && std::isfinite(m.specular) && finite(m.specular_color) &&
                std::isfinite(m.thickness) && m.attenuation_distance > 0.0f && finite(m.attenuation_color),
            "material '" + m.name + "': a non-finite factor");
    check_texture_ref(scene, m.base_color_texture, "material '" + m.name + "' base colour");
    check_texture_ref(scene, m.metallic_roughness_texture, "material '" + m.name + "' metallic-roughness");
    check_texture_ref(scene, m.emissive_texture, "material '" + m.name + "' emissive");
    check_texture_ref(scene, m.normal_texture, "material '" + m.name + "' normal");
    check_texture_ref(scene, m.occlusion_texture, "material '" + m.name + "' occlusion");
    check_texture_ref(scene, m.transmission_texture, "material '" + m.name + "' transmission");
    check_texture_ref(scene, m.specular_texture, "material '" + m.name + "' specular");
    check_texture_ref(scene, m.specular_color_texture, "material '" + m.name + "' specular colour");
    check_texture_ref(scene, m.thickness_texture, "material '" + m.name + "' thickness");
  }
  for (const Texture& t : scene.textures)
    require(t.image >= -1 && (t.image < 0 || std::size_t(t.image) < scene.images.size()), "texture image out of range");
  for (const Image& img : scene.images)
    require(img.width > 0 && img.height > 0 && img.channels >= 1 && img.channels <= 4 &&
                img.pixels.size() == std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels),
            "image '" + img.name + "': pixel count does not match its size");
  for (const CameraDesc& cam : scene.cameras) {
    require(cam.yfov > 0.0f && cam.yfov < 3.1416f, "camera '" + cam.name + "': yfov out of (0, pi)");
    for (int col = 0; col < 4; ++col)
      require(finite(cam.camera_to_world[col]), "camera '" + cam.name + "': non-finite transform");
    require(!cam.aperture_radius || (std::isfinite(*cam.aperture_radius) && *cam.aperture_radius >= 0.0f),
            "camera '" + cam.name + "': bad aperture");
    require(!cam.focus_distance || (std::isfinite(*cam.focus_distance) && *cam.focus_distance > 0.0f),
            "camera '" + cam.name + "': bad focus distance");
  }
  for (const PunctualLight& l : scene.lights)
    require(finite(l.color) && std::isfinite(l.intensity) && finite(l.position) && finite(l.direction) &&
                std::isfinite(l.range),
            "light '" + l.name + "': a non-finite parameter");
}

}  // namespace lancer::fuzz
