#include "scene/gltf_accessors.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kUByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int kUShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kInt = TINYGLTF_COMPONENT_TYPE_INT;
constexpr int kUInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

std::size_t component_size(int type) {
  switch (type) {
    case kByte:
    case kUByte:
      return 1;
    case kShort:
    case kUShort:
      return 2;
    case kInt:
    case kUInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

std::string component_name(int type) {
  switch (type) {
    case kByte:
      return "BYTE";
    case kUByte:
      return "UNSIGNED_BYTE";
    case kShort:
      return "SHORT";
    case kUShort:
      return "UNSIGNED_SHORT";
    case kInt:
      return "INT";
    case kUInt:
      return "UNSIGNED_INT";
    case kFloat:
      return "FLOAT";
    default:
      return "component type " + std::to_string(type);
  }
}

std::string type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "type " + std::to_string(type);
  }
}

// a * b + c without wrapping; false on overflow.
bool mul_add(std::size_t a, std::size_t b, std::size_t c, std::size_t& out) {
  std::size_t product = 0;
  return !__builtin_mul_overflow(a, b, &product) && !__builtin_add_overflow(product, c, &out);
}

// What a use of an accessor allows.
struct Requirement {
  int type;               // TINYGLTF_TYPE_*
  int components;         // elements per vector
  const char* described;  // for messages
  bool (*allowed)(int component_type, bool normalized);
};

// Where an accessor's elements are. `base` is null when the accessor has no
// bufferView (all elements zero before sparse substitution).
struct Layout {
  const tinygltf::Accessor* accessor = nullptr;
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
  std::size_t component_size = 0;
  std::size_t element_size = 0;
};

Layout layout_of(const ModelRef& m, int index, const std::string& what, const Requirement& req) {
  const auto& accessors = m.model.accessors;
  if (index < 0 || std::size_t(index) >= accessors.size())
    throw SceneError(m.file, what + ": accessor index " + std::to_string(index) + " out of range (the file has " +
                                 std::to_string(accessors.size()) + " accessors)");
  const tinygltf::Accessor& a = accessors[std::size_t(index)];
  const std::string name = what + " (accessor " + std::to_string(index) + ")";
  if (a.type != req.type || !req.allowed(a.componentType, a.normalized))
    throw SceneError(m.file, name + " must be " + req.described + ", but it is " + type_name(a.type) + " of " +
                                 (a.normalized ? "normalized " : "") + component_name(a.componentType));

  Layout l;
  l.accessor = &a;
  l.count = a.count;
  l.component_size = component_size(a.componentType);
  l.element_size = l.component_size * std::size_t(req.components);
  if (a.bufferView < 0) {
    if (l.count > kMaxZeroFilledElements)
      throw SceneError(m.file, name + " has no bufferView and claims " + std::to_string(l.count) +
                                   " elements, more than the limit of " + std::to_string(kMaxZeroFilledElements));
    return l;
  }
  const ByteSpan view = buffer_view_bytes(m, a.bufferView, name);
  const std::size_t declared_stride = m.model.bufferViews[std::size_t(a.bufferView)].byteStride;
  l.stride = declared_stride == 0 ? l.element_size : declared_stride;
  if (declared_stride != 0) {
    // glTF 2.0 spec, bufferView.byteStride: 4 <= stride <= 252, a multiple of 4, and
    // at least the element size (elements may interleave but not overlap).
    if (declared_stride < l.element_size)
      throw SceneError(m.file, name + ": bad byteStride " + std::to_string(declared_stride) +
                                   ", smaller than the element size " + std::to_string(l.element_size));
    if (declared_stride % 4 != 0 || declared_stride > 252)
      throw SceneError(m.file, name + ": bad byteStride " + std::to_string(declared_stride) +
                                   " (must be a multiple of 4 between 4 and 252)");
  }
  if (l.count == 0) return l;
  // The last element ends at byteOffset + stride * (count - 1) + element size.
  std::size_t end = 0;
  if (!mul_add(l.stride, l.count - 1, l.element_size, end) || __builtin_add_overflow(end, a.byteOffset, &end) ||
      end > view.size)
    throw SceneError(m.file, name + " runs past the end of its bufferView " + std::to_string(a.bufferView) + ": " +
                                 std::to_string(l.count) + " elements of " + std::to_string(l.element_size) +
                                 " bytes (stride " + std::to_string(l.stride) + ") from offset " +
                                 std::to_string(a.byteOffset) + " do not fit in " + std::to_string(view.size) +
                                 " bytes");
  l.base = view.data + a.byteOffset;
  return l;
}

std::uint32_t read_unsigned(const unsigned char* p, int component_type) {
  switch (component_type) {
    case kUByte:
      return p[0];
    case kUShort: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// One component as a float: integers as they are, or mapped to [0, 1] (unsigned) or
// [-1, 1] (signed, max(c / max, -1)) when normalized (glTF 2.0, "Animations" and
// KHR_mesh_quantization give the same rules).
float read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case kUByte:
      return normalized ? float(p[0]) / 255.0f : float(p[0]);
    case kUShort:
      return normalized ? float(read_unsigned(p, kUShort)) / 65535.0f : float(read_unsigned(p, kUShort));
    case kByte: {
      const float c = float(static_cast<std::int8_t>(p[0]));
      return normalized ? std::max(c / 127.0f, -1.0f) : c;
    }
    case kShort: {
      const float c = float(static_cast<std::int16_t>(read_unsigned(p, kUShort)));
      return normalized ? std::max(c / 32767.0f, -1.0f) : c;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Calls write(element index, pointer to the substituted element) for each sparse
// entry, after checking the sparse indices and values lie in their bufferViews.
template <typename Write>
void apply_sparse(const ModelRef& m, int index, const std::string& what, const Layout& l, Write write) {
  const auto& sparse = l.accessor->sparse;
  if (!sparse.isSparse) return;
  const std::string name = what + " (accessor " + std::to_string(index) + ") sparse";
  if (sparse.count < 1 || std::size_t(sparse.count) > l.count)
    throw SceneError(m.file, name + " count " + std::to_string(sparse.count) + " out of range (the accessor has " +
                                 std::to_string(l.count) + " elements)");
  const int index_type = sparse.indices.componentType;
  if (index_type != kUByte && index_type != kUShort && index_type != kUInt)
    throw SceneError(m.file, name + " indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not " +
                                 component_name(index_type));
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
    throw SceneError(m.file, name + " has a negative byteOffset");
  const std::size_t n = std::size_t(sparse.count);
  const std::size_t index_size = component_size(index_type);
  const ByteSpan indices = buffer_view_bytes(m, sparse.indices.bufferView, name + " indices");
  const ByteSpan values = buffer_view_bytes(m, sparse.values.bufferView, name + " values");
  std::size_t end = 0;
  if (!mul_add(n, index_size, std::size_t(sparse.indices.byteOffset), end) || end > indices.size)
    throw SceneError(m.file, name + " indices run past the end of their bufferView");
  if (!mul_add(n, l.element_size, std::size_t(sparse.values.byteOffset), end) || end > values.size)
    throw SceneError(m.file, name + " values run past the end of their bufferView");
  const unsigned char* index_base = indices.data + sparse.indices.byteOffset;
  const unsigned char* value_base = values.data + sparse.values.byteOffset;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t target = read_unsigned(index_base + k * index_size, index_type);
    if (target >= l.count)
      throw SceneError(m.file, name + " index " + std::to_string(target) + " out of range (the accessor has " +
                                   std::to_string(l.count) + " elements)");
    write(target, value_base + k * l.element_size);
  }
}

template <int N>
std::vector<glm::vec<N, float>> read_float_vectors(const ModelRef& m, int index, const std::string& what,
                                                   const Requirement& req) {
  const Layout l = layout_of(m, index, what, req);
  const int ctype = l.accessor->componentType;
  const bool normalized = l.accessor->normalized;
  std::vector<glm::vec<N, float>> out(l.count, glm::vec<N, float>(0.0f));
  auto decode = [&](glm::vec<N, float>& v, const unsigned char* p) {
    for (int c = 0; c < N; ++c) v[c] = read_component(p + std::size_t(c) * l.component_size, ctype, normalized);
  };
  if (l.base)
    for (std::size_t k = 0; k < l.count; ++k) decode(out[k], l.base + k * l.stride);
  apply_sparse(m, index, what, l, [&](std::uint32_t k, const unsigned char* p) { decode(out[k], p); });
  return out;
}

bool float_only(int component_type, bool /*normalized*/) { return component_type == kFloat; }

bool texcoord_types(int component_type, bool normalized) {
  return component_type == kFloat || (normalized && (component_type == kUByte || component_type == kUShort));
}

// KHR_mesh_quantization, "Extending Mesh Attributes": what each attribute may also be.
bool integer_component(int component_type) {
  return component_type == kByte || component_type == kUByte || component_type == kShort || component_type == kUShort;
}
bool quantized_position_types(int component_type, bool /*normalized*/) {
  return component_type == kFloat || integer_component(component_type);
}
bool quantized_direction_types(int component_type, bool normalized) {
  return component_type == kFloat || (normalized && (component_type == kByte || component_type == kShort));
}
bool quantized_texcoord_types(int component_type, bool /*normalized*/) {
  return component_type == kFloat || integer_component(component_type);
}

bool index_types(int component_type, bool normalized) {
  return !normalized && (component_type == kUByte || component_type == kUShort || component_type == kUInt);
}

}  // namespace

int json_index(const tinygltf::Value& v) {
  if (!v.IsInt() && !v.IsNumber()) return -1;
  const double d = v.GetNumberAsDouble();
  return d >= 0.0 && d <= double(INT_MAX) && d == std::floor(d) ? int(d) : -1;
}

ByteSpan buffer_view_bytes(const ModelRef& m, int view, const std::string& what) {
  const auto& views = m.model.bufferViews;
  if (view < 0 || std::size_t(view) >= views.size())
    throw SceneError(m.file, what + ": bufferView index " + std::to_string(view) + " out of range (the file has " +
                                 std::to_string(views.size()) + " bufferViews)");
  const tinygltf::BufferView& bv = views[std::size_t(view)];
  if (bv.buffer < 0 || std::size_t(bv.buffer) >= m.model.buffers.size())
    throw SceneError(m.file, what + ": bufferView " + std::to_string(view) + " refers to buffer " +
                                 std::to_string(bv.buffer) + ", out of range (the file has " +
                                 std::to_string(m.model.buffers.size()) + " buffers)");
  const std::vector<unsigned char>& data = m.model.buffers[std::size_t(bv.buffer)].data;
  std::size_t end = 0;
  if (__builtin_add_overflow(bv.byteOffset, bv.byteLength, &end) || end > data.size())
    throw SceneError(m.file, what + ": bufferView " + std::to_string(view) + " (offset " +
                                 std::to_string(bv.byteOffset) + ", length " + std::to_string(bv.byteLength) +
                                 ") runs past the end of buffer " + std::to_string(bv.buffer) + " (" +
                                 std::to_string(data.size()) + " bytes)");
  return {data.data() + bv.byteOffset, bv.byteLength};
}

bool uses_mesh_quantization(const ModelRef& m) {
  for (const std::string& name : m.model.extensionsUsed)
    if (name == "KHR_mesh_quantization") return true;
  return false;
}

std::vector<glm::vec3> read_positions(const ModelRef& m, int accessor, const std::string& what) {
  if (!uses_mesh_quantization(m))
    return read_float_vectors<3>(
        m, accessor, what,
        {TINYGLTF_TYPE_VEC3, 3, "VEC3 of FLOAT (integers need the file to use KHR_mesh_quantization)", float_only});
  return read_float_vectors<3>(m, accessor, what,
                               {TINYGLTF_TYPE_VEC3, 3,
                                "VEC3 of FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT (KHR_mesh_quantization)",
                                quantized_position_types});
}

std::vector<glm::vec3> read_normals(const ModelRef& m, int accessor, const std::string& what) {
  if (!uses_mesh_quantization(m))
    return read_float_vectors<3>(
        m, accessor, what,
        {TINYGLTF_TYPE_VEC3, 3, "VEC3 of FLOAT (integers need the file to use KHR_mesh_quantization)", float_only});
  return read_float_vectors<3>(
      m, accessor, what,
      {TINYGLTF_TYPE_VEC3, 3, "VEC3 of FLOAT or of normalized BYTE/SHORT (KHR_mesh_quantization)",
       quantized_direction_types});
}

std::vector<glm::vec4> read_tangents(const ModelRef& m, int accessor, const std::string& what) {
  if (!uses_mesh_quantization(m))
    return read_float_vectors<4>(
        m, accessor, what,
        {TINYGLTF_TYPE_VEC4, 4, "VEC4 of FLOAT (integers need the file to use KHR_mesh_quantization)", float_only});
  return read_float_vectors<4>(
      m, accessor, what,
      {TINYGLTF_TYPE_VEC4, 4, "VEC4 of FLOAT or of normalized BYTE/SHORT (KHR_mesh_quantization)",
       quantized_direction_types});
}

std::vector<glm::vec2> read_texcoords(const ModelRef& m, int accessor, const std::string& what) {
  if (uses_mesh_quantization(m))
    return read_float_vectors<2>(m, accessor, what,
                                 {TINYGLTF_TYPE_VEC2, 2,
                                  "VEC2 of FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT (KHR_mesh_quantization)",
                                  quantized_texcoord_types});
  return read_float_vectors<2>(
      m, accessor, what,
      {TINYGLTF_TYPE_VEC2, 2, "VEC2 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT", texcoord_types});
}

std::vector<glm::vec4> read_rotations(const ModelRef& m, int accessor, const std::string& what) {
  return read_float_vectors<4>(m, accessor, what,
                               {TINYGLTF_TYPE_VEC4, 4, "VEC4 of FLOAT or of normalized BYTE/SHORT",
                                quantized_direction_types});
}

namespace {
bool joint_types(int component_type, bool normalized) {
  return !normalized && (component_type == kUByte || component_type == kUShort);
}
}  // namespace

std::vector<glm::uvec4> read_joints(const ModelRef& m, int accessor, const std::string& what) {
  const std::vector<glm::vec4> j = read_float_vectors<4>(
      m, accessor, what, {TINYGLTF_TYPE_VEC4, 4, "VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT", joint_types});
  std::vector<glm::uvec4> out(j.size());
  for (std::size_t k = 0; k < j.size(); ++k) out[k] = glm::uvec4(j[k]);  // exact: at most 65535
  return out;
}

std::vector<glm::vec4> read_weights(const ModelRef& m, int accessor, const std::string& what) {
  return read_float_vectors<4>(
      m, accessor, what,
      {TINYGLTF_TYPE_VEC4, 4, "VEC4 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT", texcoord_types});
}

namespace {
bool animation_weight_types(int component_type, bool normalized) {
  return component_type == kFloat || (normalized && integer_component(component_type));
}
std::vector<float> first_components(const std::vector<glm::vec<1, float>>& v) {
  std::vector<float> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = v[k].x;
  return out;
}
}  // namespace

std::vector<float> read_animation_times(const ModelRef& m, int accessor, const std::string& what) {
  return first_components(
      read_float_vectors<1>(m, accessor, what, {TINYGLTF_TYPE_SCALAR, 1, "SCALAR of FLOAT", float_only}));
}

std::vector<glm::vec3> read_animation_vec3(const ModelRef& m, int accessor, const std::string& what) {
  return read_float_vectors<3>(m, accessor, what, {TINYGLTF_TYPE_VEC3, 3, "VEC3 of FLOAT", float_only});
}

std::vector<float> read_animation_weights(const ModelRef& m, int accessor, const std::string& what) {
  return first_components(read_float_vectors<1>(
      m, accessor, what,
      {TINYGLTF_TYPE_SCALAR, 1, "SCALAR of FLOAT or of normalized BYTE/UNSIGNED_BYTE/SHORT/UNSIGNED_SHORT",
       animation_weight_types}));
}

std::vector<glm::mat4> read_mat4_floats(const ModelRef& m, int accessor, const std::string& what) {
  const Layout l = layout_of(m, accessor, what, {TINYGLTF_TYPE_MAT4, 16, "MAT4 of FLOAT", float_only});
  std::vector<glm::mat4> out(l.count, glm::mat4(0.0f));
  auto decode = [&](glm::mat4& v, const unsigned char* p) {
    for (int c = 0; c < 16; ++c) v[c / 4][c % 4] = read_component(p + std::size_t(c) * 4, kFloat, false);
  };
  if (l.base)
    for (std::size_t k = 0; k < l.count; ++k) decode(out[k], l.base + k * l.stride);
  apply_sparse(m, accessor, what, l, [&](std::uint32_t k, const unsigned char* p) { decode(out[k], p); });
  return out;
}

std::vector<glm::vec4> read_colors(const ModelRef& m, int accessor, const std::string& what) {
  const char* described = "VEC3 or VEC4 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT";
  const auto& accessors = m.model.accessors;
  const bool rgb = accessor >= 0 && std::size_t(accessor) < accessors.size() &&
                   accessors[std::size_t(accessor)].type == TINYGLTF_TYPE_VEC3;
  std::vector<glm::vec4> out;
  if (rgb) {
    const std::vector<glm::vec3> c =
        read_float_vectors<3>(m, accessor, what, {TINYGLTF_TYPE_VEC3, 3, described, texcoord_types});
    out.reserve(c.size());
    for (const glm::vec3& v : c) out.emplace_back(v, 1.0f);
  } else {
    out = read_float_vectors<4>(m, accessor, what, {TINYGLTF_TYPE_VEC4, 4, described, texcoord_types});
  }
  for (glm::vec4& v : out)
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(v[c])) throw SceneError(m.file, what + " holds a non-finite colour component");
      v[c] = v[c] < 0.0f ? 0.0f : (v[c] > 1.0f ? 1.0f : v[c]);
    }
  return out;
}

std::vector<std::uint32_t> read_indices(const ModelRef& m, int accessor, const std::string& what) {
  const Requirement req{TINYGLTF_TYPE_SCALAR, 1, "SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                        index_types};
  const Layout l = layout_of(m, accessor, what, req);
  const int ctype = l.accessor->componentType;
  std::vector<std::uint32_t> out(l.count, 0u);
  if (l.base)
    for (std::size_t k = 0; k < l.count; ++k) out[k] = read_unsigned(l.base + k * l.stride, ctype);
  apply_sparse(m, accessor, what, l,
               [&](std::uint32_t k, const unsigned char* p) { out[k] = read_unsigned(p, ctype); });
  return out;
}

}  // namespace lancer::gltf
