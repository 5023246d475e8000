// Bounds-checked reads of glTF accessors. tinygltf checks almost none of an
// accessor's arithmetic, so everything is verified here before a byte is read or an
// element allocated: accessor and bufferView ids, byteStride, that
// byteOffset + stride * (count - 1) + element size fits in the bufferView, that the
// bufferView fits in its buffer, the types an attribute may have, and sparse data.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
class Value;
}

namespace lancer::gltf {

// A loaded model and the file name used in error messages.
struct ModelRef {
  const tinygltf::Model& model;
  const std::string& file;
  int scene = -1;  // the glTF scene to load (--scene); -1: the file's default scene
};

// The largest accessor without a bufferView (all zeros, typically the base of a
// sparse accessor) that is materialised; its size is not bounded by any buffer.
inline constexpr std::size_t kMaxZeroFilledElements = std::size_t(1) << 24;

// `what` names the accessor's use in messages, e.g. "mesh 0 primitive 1 POSITION".
// Each throws SceneError when the accessor is out of range, of a type the use does not
// allow, or reaches outside its data.
// Mesh attributes. Without KHR_mesh_quantization in extensionsUsed: POSITION and NORMAL
// VEC3 of FLOAT, TANGENT VEC4 of FLOAT, TEXCOORD_n VEC2 of FLOAT or of normalized
// UNSIGNED_BYTE / UNSIGNED_SHORT. With it, also what the extension allows: POSITION and
// TEXCOORD_n of BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not (the node
// transforms or KHR_texture_transform scale them back), NORMAL and TANGENT of normalized
// BYTE or SHORT. Normalized integers map to [0, 1] or [-1, 1] as the spec says.
bool uses_mesh_quantization(const ModelRef& m);
std::vector<glm::vec3> read_positions(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::vec3> read_normals(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::vec4> read_tangents(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::vec2> read_texcoords(const ModelRef& m, int accessor, const std::string& what);
// Quaternions (x, y, z, w): VEC4 of FLOAT or of normalized BYTE/SHORT (as animation
// samplers and EXT_mesh_gpu_instancing allow).
std::vector<glm::vec4> read_rotations(const ModelRef& m, int accessor, const std::string& what);
// Skinning (glTF 2.0, "Skinned Mesh Attributes"): JOINTS_n VEC4 of UNSIGNED_BYTE or
// UNSIGNED_SHORT; WEIGHTS_n VEC4 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT;
// inverseBindMatrices MAT4 of FLOAT (column-major, as glm).
std::vector<glm::uvec4> read_joints(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::vec4> read_weights(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::mat4> read_mat4_floats(const ModelRef& m, int accessor, const std::string& what);
// Animation samplers (glTF 2.0, "Animations"): input times SCALAR of FLOAT; translation
// and scale outputs VEC3 of FLOAT (rotations: read_rotations); morph weights SCALAR of
// FLOAT or of normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT.
std::vector<float> read_animation_times(const ModelRef& m, int accessor, const std::string& what);
std::vector<glm::vec3> read_animation_vec3(const ModelRef& m, int accessor, const std::string& what);
std::vector<float> read_animation_weights(const ModelRef& m, int accessor, const std::string& what);
// COLOR_0: VEC3 or VEC4 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT, as linear
// RGBA (alpha 1 for VEC3). A non-finite float is an error; floats outside [0, 1] are
// clamped to it (the range the specification gives colours).
std::vector<glm::vec4> read_colors(const ModelRef& m, int accessor, const std::string& what);
// SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT.
std::vector<std::uint32_t> read_indices(const ModelRef& m, int accessor, const std::string& what);

// An extension's JSON value that must be an index: an integer in [0, INT_MAX], else -1
// (never an out-of-range conversion of a huge or fractional number).
int json_index(const tinygltf::Value& v);

// The bytes [offset, offset + length) of bufferView `view`, checked to lie in its buffer.
struct ByteSpan {
  const unsigned char* data = nullptr;
  std::size_t size = 0;
};
ByteSpan buffer_view_bytes(const ModelRef& m, int view, const std::string& what);

}  // namespace lancer::gltf
