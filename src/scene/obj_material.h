// MTL materials onto Lancer's glTF metallic-roughness Material, and the MTL's texture
// maps into scene.textures / scene.images (decoded with stb_image, shared by path).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include <tiny_obj_loader.h>

#include "scene/scene.h"

namespace lancer::obj_detail {

// Phong exponent Ns to glTF perceptual roughness (see obj_material.cpp).
float roughness_from_phong_exponent(float ns);

// The material faces without `usemtl` (or with an unknown name) get.
Material default_obj_material();

// Loads each texture file once into `scene`; errors name the OBJ file and the texture.
class ObjTextureLoader {
 public:
  ObjTextureLoader(Scene& scene, std::string obj_file) : scene_(scene), obj_file_(std::move(obj_file)) {}

  // `texname` as written in the MTL, resolved against `mtl_dir`. Throws SceneError when
  // the file is missing or cannot be decoded.
  TextureRef load(const std::string& texname, const tinyobj::texture_option_t& option,
                  const std::filesystem::path& mtl_dir, const std::string& material_name);

 private:
  int load_image(const std::filesystem::path& path, const std::string& texname, const std::string& material_name);

  Scene& scene_;
  std::string obj_file_;
  std::map<std::string, int> image_by_path_;
  std::map<std::pair<int, bool>, int> texture_by_image_and_clamp_;
};

// Converts one MTL material. Textures are resolved against `mtl_dir`, the folder of
// the MTL file the material came from. Throws SceneError on non-finite parameters.
Material convert_mtl_material(const tinyobj::material_t& mtl, const std::filesystem::path& mtl_dir,
                              ObjTextureLoader& textures, const std::string& obj_file);

}  // namespace lancer::obj_detail
