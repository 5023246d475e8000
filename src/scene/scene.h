// A loaded scene, flattened: world-space triangles in SoA form for the accelerators,
// plus everything shading needs (per-corner attributes, materials, textures, cameras,
// punctual lights). Readers (glTF, OBJ, procedural) fill it; they know no accelerator.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "accel/instances.h"
#include "accel/triangle_soa.h"

namespace lancer {

enum class AlphaMode { Opaque, Mask, Blend };

// A reference from a material to scene.textures, with its texcoord set and, for normal
// and occlusion textures, the scale/strength.
struct TextureRef {
  int texture = -1;
  int texcoord = 0;  // 0 or 1 (TEXCOORD_0 / TEXCOORD_1); KHR_texture_transform may override it
  float scale = 1.0f;
  // KHR_texture_transform: uv' = (transform * vec3(uv, 1)).xy, the extension's
  // offset * rotation * scale; the identity when the extension is absent.
  glm::mat3 transform{1.0f};
  bool present() const { return texture >= 0; }
};

// The glTF 2.0 metallic-roughness material and the extensions Lancer reads.
// Colour factors are linear; colour textures are sRGB-encoded.
struct Material {
  std::string name;
  glm::vec4 base_color{1.0f};
  TextureRef base_color_texture;
  float metallic = 1.0f;
  float roughness = 1.0f;
  TextureRef metallic_roughness_texture;  // roughness in G, metallic in B
  glm::vec3 emissive_factor{0.0f};
  float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
  TextureRef emissive_texture;
  TextureRef normal_texture;
  TextureRef occlusion_texture;
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  float ior = 1.5f;                 // KHR_materials_ior
  float transmission = 0.0f;        // KHR_materials_transmission
  float specular = 1.0f;            // KHR_materials_specular
  glm::vec3 specular_color{1.0f};
  TextureRef transmission_texture;    // KHR_materials_transmission: factor in R
  TextureRef specular_texture;        // KHR_materials_specular: factor in A (linear)
  TextureRef specular_color_texture;  // KHR_materials_specular: colour in RGB (sRGB)
  // KHR_materials_volume: thickness in the mesh's own units (thickness texture in G),
  // and the distance light travels in the medium before it is attenuated to
  // attenuation_color (infinity: no attenuation).
  float thickness = 0.0f;
  TextureRef thickness_texture;
  float attenuation_distance = std::numeric_limits<float>::infinity();
  glm::vec3 attenuation_color{1.0f};
  // KHR_materials_clearcoat: layer weight (texture R), perceptual roughness (texture G) and
  // the coat's own normal map (absent: the interpolated normal, not normal_texture).
  float clearcoat = 0.0f;
  TextureRef clearcoat_texture;
  float clearcoat_roughness = 0.0f;
  TextureRef clearcoat_roughness_texture;
  TextureRef clearcoat_normal_texture;
  // KHR_materials_sheen: linear colour (texture RGB, sRGB) and roughness (texture A, linear).
  glm::vec3 sheen_color{0.0f};
  TextureRef sheen_color_texture;
  float sheen_roughness = 0.0f;
  TextureRef sheen_roughness_texture;
  // KHR_materials_unlit: the surface shows its base colour and scatters no light.
  bool unlit = false;

  // Emitted radiance (W / (sr m^2)): glTF's emissive factor times strength, nothing else.
  glm::vec3 emission() const { return emissive_factor * emissive_strength; }
  bool emissive() const { return emission() != glm::vec3(0.0f); }

  // Whether any of the material's textures reads texture coordinate set `set`.
  bool uses_texcoord(int set) const {
    for (const TextureRef* t : {&base_color_texture, &metallic_roughness_texture, &emissive_texture, &normal_texture,
                                &occlusion_texture, &transmission_texture, &specular_texture, &specular_color_texture,
                                &thickness_texture, &clearcoat_texture, &clearcoat_roughness_texture,
                                &clearcoat_normal_texture, &sheen_color_texture, &sheen_roughness_texture})
      if (t->present() && t->texcoord == set) return true;
    return false;
  }
};

// glTF sampler enums kept as numbers (10497 repeat, 33071 clamp, 33648 mirrored repeat).
struct Texture {
  int image = -1;
  int wrap_s = 10497;
  int wrap_t = 10497;
  int mag_filter = -1;
  int min_filter = -1;
};

// Decoded 8-bit image, rows top to bottom.
struct Image {
  std::string name;  // file path or a description of an embedded image
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> pixels;
};

struct CameraDesc {
  std::string name;
  // The number `--camera` selects: the camera's index in the glTF file's cameras (a camera
  // placed by several nodes is known by its first placement), else its place in the list.
  int index = 0;
  glm::mat4 camera_to_world{1.0f};  // camera looks down -z, +y up (glTF convention)
  float yfov = 0.8f;                // radians (perspective)
  std::optional<float> aspect_ratio;
  // glTF "orthographic": parallel rays along -z; the view spans [-xmag, xmag] x [-ymag,
  // ymag] in the camera's x and y (scene units; a negative magnification mirrors).
  bool orthographic = false;
  float xmag = 1.0f, ymag = 1.0f;
  // A thin lens, from the glTF camera's extras {"aperture": r, "focusDistance": d} (a
  // Lancer convention; glTF itself has no lens): lens radius r >= 0 and distance d > 0 to
  // the plane in focus, both in scene units. No focus distance: focused at infinity.
  std::optional<float> aperture_radius;
  std::optional<float> focus_distance;
  // --shutter: camera_to_world at the shutter's kShutterSteps times when the camera node
  // moves while it is open (instances.h's keys); empty for a still camera.
  std::vector<MotionKey> motion;
};

enum class LightType { Point, Spot, Directional };

// KHR_lights_punctual in the extension's units: intensity in candela (point, spot)
// or lux (directional); colour linear.
struct PunctualLight {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // direction the light shines, world space
  float range = 0.0f;                       // 0: unlimited
  float inner_cone = 0.0f;
  float outer_cone = 0.7853981634f;
};

// What a reader skipped or repaired; reported to the user.
struct LoadStats {
  std::size_t degenerate_dropped = 0;  // zero-area triangles
  std::size_t non_triangle_primitives_skipped = 0;  // points and lines
  std::size_t zero_normals_repaired = 0;
};

// Per-triangle flags saying which per-corner attributes are real.
enum TriangleAttrib : std::uint8_t {
  kHasNormals = 1,
  kHasTexcoords = 2,
  kHasTangents = 4,
  kHasTexcoords1 = 8,
  kHasColors = 16,
};

// A glTF file's animations, as far as lancer poses them: how many there are, and the
// channels and keyframe times of the first (the one --frame-time samples).
struct AnimationRange {
  std::size_t animations = 0;
  std::size_t channels = 0;
  double start = 0.0, end = 0.0;  // seconds: the first and last keyframe of any channel
};

// Whether meshes drawn more than once are stored once and drawn through instances
// (`--instancing`): Auto when the copies would add at least kInstancingMinTriangles
// triangles, On whenever a mesh is drawn twice, Off never (every copy in world space).
enum class InstancingMode { Auto, On, Off };
inline constexpr std::size_t kInstancingMinTriangles = std::size_t(1) << 16;

// Motion blur (`--shutter OPEN,CLOSE`, seconds on the first animation's timeline): what
// moves while the shutter is open is sampled at kShutterSteps evenly spaced times.
struct Shutter {
  double open = 0.0, close = 0.0;
};
inline constexpr int kShutterSteps = 17;

struct Scene {
  std::string source;  // file it came from, or the procedural scene's name
  // What the reader warned about while loading (load_scene), one line each, without the
  // "lancer: warning: FILE: " prefix: mostly what the file uses that Lancer ignores.
  std::vector<std::string> warnings;

  // Geometry. Triangle i has corners 3i, 3i+1, 3i+2 in the per-corner arrays below.
  // In world space, unless `instancing` is not empty: then each triangle belongs to one
  // mesh, stored in its own space and drawn through instances, and every per-corner
  // attribute below is in that space too.
  TriangleSoA triangles;
  InstancedGeometry instancing;
  // Per instance: what source_triangle_id of its mesh's triangles is offset by, so each
  // drawing keeps the ids a flattened copy of the file would give (source_id()); kNoHit
  // for an instance numbered past 2^32 drawn triangles.
  std::vector<std::uint32_t> instance_source_base;
  std::vector<std::uint32_t> material_id;         // per triangle, index into materials
  std::vector<std::uint32_t> source_triangle_id;  // per triangle: position among the file's triangles
  std::vector<std::uint8_t> attrib_flags;         // per triangle, TriangleAttrib bits
  // Per-corner attributes. Each is empty when no triangle has it (a mesh without normals
  // or texture coordinates costs nothing for them), else 3 * triangle_count() long, with
  // zeros at the corners of triangles whose attrib_flags bit is clear.
  std::vector<glm::vec3> normals;     // world space, unit length (kHasNormals)
  std::vector<glm::vec2> texcoords;   // TEXCOORD_0 (kHasTexcoords)
  std::vector<glm::vec4> tangents;    // xyz world space, w handedness (kHasTangents)
  std::vector<glm::vec2> texcoords1;  // TEXCOORD_1, filled only for materials that use set 1
  std::vector<glm::vec4> colors;      // COLOR_0, linear RGBA (alpha 1 for RGB) (kHasColors)

  std::vector<Material> materials;  // never empty once loaded: a default material is added
  std::vector<Texture> textures;
  std::vector<Image> images;
  std::vector<CameraDesc> cameras;
  std::vector<PunctualLight> lights;
  LoadStats stats;
  AnimationRange animation;

  // Triangles stored (a mesh drawn through many instances counts once).
  std::size_t triangle_count() const { return triangles.size(); }
  // Triangles drawn: each instance counts its mesh's.
  std::size_t drawn_triangle_count() const;
  // World-space bounds of everything drawn.
  Bounds3 bounds() const;
  // The instance `instance` of a hit draws through, or null when the triangle is stored in
  // world space (kNoHit, or a still instance whose transforms are the identity). A moving
  // one is as at the shutter's opening: drawn_instance (render/drawn_triangle.h) moves it.
  const Instance* instance_transform(std::uint32_t instance) const {
    if (instance == kNoHit) return nullptr;
    const Instance& inst = instancing.instances[instance];
    const bool identity = inst.motion == kNoHit && inst.to_world.linear == glm::mat3(1.0f) &&
                          inst.to_world.offset == glm::vec3(0.0f);
    return identity ? nullptr : &inst;
  }
  // The triangle's id among the file's triangles, as a flattened copy would number it
  // (kNoHit past 2^32 drawn triangles).
  std::uint32_t source_id(std::uint32_t prim, std::uint32_t instance) const {
    const std::uint32_t local = prim < source_triangle_id.size() ? source_triangle_id[prim] : prim;
    if (instance == kNoHit || instance >= instance_source_base.size()) return local;
    const std::uint32_t base = instance_source_base[instance];
    return base == kNoHit ? kNoHit : base + local;
  }
};

}  // namespace lancer
