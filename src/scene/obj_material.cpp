#include "scene/obj_material.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

#include <glm/common.hpp>

#include "scene/image_decode.h"
#include "scene/scene_error.h"

namespace lancer::obj_detail {

namespace {

namespace fs = std::filesystem;

constexpr int kRepeat = 10497;       // glTF sampler wrap modes
constexpr int kClampToEdge = 33071;

glm::vec3 to_vec3(const tinyobj::real_t v[3]) { return {v[0], v[1], v[2]}; }
float max_component(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }
glm::vec3 clamp01(const glm::vec3& v) { return glm::clamp(v, glm::vec3(0.0f), glm::vec3(1.0f)); }

void require_finite(const tinyobj::material_t& mtl, const std::string& obj_file, const char* what, const float* v,
                    int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      throw SceneError(obj_file, "material '" + mtl.name + "': " + what + " is not a finite number");
}

// MTL illumination models (Wavefront MTL spec, "illum"): 3 adds a ray-traced mirror
// reflection, 5 the same with Fresnel; 4, 6, 7 and 9 are glass (transparency or
// refraction).
bool mirror_illum(int illum) { return illum == 3 || illum == 5; }
bool glass_illum(int illum) { return illum == 4 || illum == 6 || illum == 7 || illum == 9; }

}  // namespace

// A Phong lobe of exponent Ns matches a Beckmann lobe of width alpha = sqrt(2 / (Ns + 2))
// (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", sec. 5.2);
// GGX's alpha is read the same way. glTF's roughness is perceptual: alpha = roughness^2,
// so roughness = sqrt(alpha) = (2 / (Ns + 2))^(1/4). Ns = 0 gives 1, Ns = 1000 about 0.21.
float roughness_from_phong_exponent(float ns) {
  const float alpha = std::sqrt(2.0f / (std::max(ns, 0.0f) + 2.0f));
  return std::sqrt(alpha);
}

Material default_obj_material() {
  Material m;
  m.name = "default";
  m.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.double_sided = true;  // OBJ has no winding convention that a renderer may rely on
  return m;
}

// The mapping from MTL's Phong parameters (Kd, Ks, Ns, Ke, Ni, d/Tr, illum, Tf):
// - Dielectric (default): base colour = Kd, metallic 0, roughness from Ns as above.
//   Ks only switches the specular lobe: Ks = 0 or illum 1 ("no highlight") gives
//   KHR_materials_specular specular = 0, otherwise 1 (glTF's F0 comes from the IOR).
// - Metal: illum 3/5 (mirror), or a strong Ks (max >= 0.5) over a dark Kd (max <= 0.1),
//   the usual way metals are written in MTL: metallic 1, base colour = Ks. A mirror
//   illum is a perfectly specular reflection, so roughness 0; otherwise from Ns.
// - Glass, illum 4/6/7/9: transmission 1, metallic 0, base colour = Tf when given
//   (the transmission filter), else white; d is then not used as alpha because the
//   transparency is the transmission itself. MTL's refraction models describe solids, so
//   the glass is a volume boundary (thickness > 0), not a glTF thin wall.
// - Ke -> emission. glTF keeps emissive_factor in [0, 1], so a brighter Ke is split
//   into factor * emissive_strength (KHR_materials_emissive_strength); emission() = Ke.
//   map_Ke with Ke = 0 (some exporters omit Ke) uses factor 1 so the texture shows;
//   likewise map_Kd with Kd = 0 (tinyobjloader's value for a missing Kd).
// - Ni -> ior when Ni > 1. tinyobjloader reports a missing Ni as 1.0, and an IOR of 1
//   would switch off all Fresnel reflection, so Ni <= 1 keeps glTF's default 1.5.
// - d (or Tr = 1 - d, converted by tinyobjloader) -> base colour alpha; alpha < 1 uses
//   AlphaMode::Blend.
// - map_Kd -> base colour texture (sRGB), map_Ke -> emissive texture, norm (or else
//   bump / map_Bump, which exporters such as Blender use for normal maps) -> normal
//   texture with -bm as its scale. -clamp gives clamp-to-edge wrapping.
Material convert_mtl_material(const tinyobj::material_t& mtl, const fs::path& mtl_dir, ObjTextureLoader& textures,
                              const std::string& obj_file) {
  require_finite(mtl, obj_file, "Kd", mtl.diffuse, 3);
  require_finite(mtl, obj_file, "Ks", mtl.specular, 3);
  require_finite(mtl, obj_file, "Ke", mtl.emission, 3);
  require_finite(mtl, obj_file, "Tf", mtl.transmittance, 3);
  require_finite(mtl, obj_file, "Ns", &mtl.shininess, 1);
  require_finite(mtl, obj_file, "Ni", &mtl.ior, 1);
  require_finite(mtl, obj_file, "d", &mtl.dissolve, 1);

  const glm::vec3 kd = clamp01(to_vec3(mtl.diffuse));
  const glm::vec3 ks = clamp01(to_vec3(mtl.specular));
  const glm::vec3 tf = clamp01(to_vec3(mtl.transmittance));
  const glm::vec3 ke = glm::max(to_vec3(mtl.emission), glm::vec3(0.0f));

  Material m;
  m.name = mtl.name;
  m.double_sided = true;
  m.metallic = 0.0f;
  m.roughness = roughness_from_phong_exponent(mtl.shininess);
  m.base_color = glm::vec4(kd, 1.0f);
  if (mtl.ior > 1.0f) m.ior = mtl.ior;

  if (glass_illum(mtl.illum)) {
    m.transmission = 1.0f;
    m.thickness = 1.0f;  // a refracting solid: a volume boundary, not a thin wall (KHR_materials_volume)
    m.base_color = glm::vec4(max_component(tf) > 0.0f ? tf : glm::vec3(1.0f), 1.0f);
  } else {
    const bool metal_look = max_component(ks) >= 0.5f && max_component(kd) <= 0.1f;
    if (mirror_illum(mtl.illum) || metal_look) {
      m.metallic = 1.0f;
      if (max_component(ks) > 0.0f) m.base_color = glm::vec4(ks, 1.0f);
      if (mirror_illum(mtl.illum)) m.roughness = 0.0f;
    } else if (max_component(ks) == 0.0f || mtl.illum == 1) {
      m.specular = 0.0f;
    }
    const float alpha = std::clamp(static_cast<float>(mtl.dissolve), 0.0f, 1.0f);
    m.base_color.a = alpha;
    if (alpha < 1.0f) m.alpha_mode = AlphaMode::Blend;
  }

  const float brightest = max_component(ke);
  m.emissive_factor = brightest > 1.0f ? ke / brightest : ke;
  m.emissive_strength = brightest > 1.0f ? brightest : 1.0f;

  if (!mtl.diffuse_texname.empty()) {
    m.base_color_texture = textures.load(mtl.diffuse_texname, mtl.diffuse_texopt, mtl_dir, mtl.name);
    if (max_component(glm::vec3(m.base_color)) == 0.0f) m.base_color = glm::vec4(glm::vec3(1.0f), m.base_color.a);
  }
  if (!mtl.emissive_texname.empty()) {
    m.emissive_texture = textures.load(mtl.emissive_texname, mtl.emissive_texopt, mtl_dir, mtl.name);
    if (brightest == 0.0f) m.emissive_factor = glm::vec3(1.0f);
  }
  const bool has_norm = !mtl.normal_texname.empty();
  const std::string& normal_name = has_norm ? mtl.normal_texname : mtl.bump_texname;
  const tinyobj::texture_option_t& normal_option = has_norm ? mtl.normal_texopt : mtl.bump_texopt;
  if (!normal_name.empty()) {
    m.normal_texture = textures.load(normal_name, normal_option, mtl_dir, mtl.name);
    const float scale = normal_option.bump_multiplier;
    m.normal_texture.scale = std::isfinite(scale) ? scale : 1.0f;
  }
  return m;
}

TextureRef ObjTextureLoader::load(const std::string& texname, const tinyobj::texture_option_t& option,
                                  const fs::path& mtl_dir, const std::string& material_name) {
  fs::path path = mtl_dir / fs::path(texname);
  std::error_code ec;
  if (!fs::exists(path, ec) && texname.find('\\') != std::string::npos) {
    // Files written on Windows may separate folders with backslashes.
    std::string forward = texname;
    std::replace(forward.begin(), forward.end(), '\\', '/');
    path = mtl_dir / fs::path(forward);
  }
  const int image = load_image(path, texname, material_name);
  const auto key = std::make_pair(image, option.clamp);
  auto found = texture_by_image_and_clamp_.find(key);
  if (found == texture_by_image_and_clamp_.end()) {
    Texture texture;
    texture.image = image;
    texture.wrap_s = texture.wrap_t = option.clamp ? kClampToEdge : kRepeat;
    scene_.textures.push_back(texture);
    found = texture_by_image_and_clamp_.emplace(key, static_cast<int>(scene_.textures.size() - 1)).first;
  }
  TextureRef ref;
  ref.texture = found->second;
  return ref;
}

int ObjTextureLoader::load_image(const fs::path& path, const std::string& texname, const std::string& material_name) {
  const std::string key = path.lexically_normal().string();
  if (auto found = image_by_path_.find(key); found != image_by_path_.end()) return found->second;

  const auto fail = [&](const std::string& why) {
    throw SceneError(obj_file_, "material '" + material_name + "': texture '" + texname + "' (" + path.string() +
                                    ") " + why);
  };
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail("does not exist or is not a file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail("could not be read (" + ec.message() + ")");
  if (size > std::uintmax_t(INT_MAX)) fail("is too large to decode (over 2 GiB)");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot be opened for reading");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail("could not be read");
  scene_.images.push_back(decode_image(bytes, path.string(), obj_file_,
                                       "material '" + material_name + "': texture '" + texname + "' (" +
                                           path.string() + ")"));
  const int index = static_cast<int>(scene_.images.size() - 1);
  image_by_path_.emplace(key, index);
  return index;
}

}  // namespace lancer::obj_detail
