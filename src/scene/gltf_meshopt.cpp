#include "scene/gltf_meshopt.h"

#include <tiny_gltf.h>

#include <climits>
#include <cstdint>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

using nlohmann::json;

constexpr const char* kExtension = "EXT_meshopt_compression";

// obj.extensions.EXT_meshopt_compression, or null.
const json* extension_of(const json& obj) {
  const auto extensions = obj.find("extensions");
  if (extensions == obj.end() || !extensions->is_object()) return nullptr;
  const auto ext = extensions->find(kExtension);
  return ext == extensions->end() ? nullptr : &*ext;
}

// A non-negative integer property (check_gltf_json has checked the types of those present).
std::size_t size_property(const std::string& file, const json& ext, const char* key, bool required,
                          const std::string& what) {
  const auto it = ext.find(key);
  if (it == ext.end()) {
    if (required) throw SceneError(file, what + " needs '" + key + "'");
    return 0;
  }
  if (!it->is_number_integer() || (!it->is_number_unsigned() && it->get<std::int64_t>() < 0))
    throw SceneError(file, what + ": '" + key + "' must be a non-negative integer");
  return std::size_t(it->get<std::uint64_t>());
}

std::string string_property(const std::string& file, const json& ext, const char* key, const char* fallback,
                            const std::string& what) {
  const auto it = ext.find(key);
  if (it == ext.end()) {
    if (!fallback) throw SceneError(file, what + " needs '" + key + "'");
    return fallback;
  }
  if (!it->is_string()) throw SceneError(file, what + ": '" + key + "' must be a string");
  return it->get<std::string>();
}

MeshoptMode mode_of(const std::string& file, const std::string& name, const std::string& what) {
  if (name == "ATTRIBUTES") return MeshoptMode::Attributes;
  if (name == "TRIANGLES") return MeshoptMode::Triangles;
  if (name == "INDICES") return MeshoptMode::Indices;
  throw SceneError(file, what + ": unknown mode '" + name + "' (expected ATTRIBUTES, TRIANGLES or INDICES)");
}

MeshoptFilter filter_of(const std::string& file, const std::string& name, const std::string& what) {
  if (name == "NONE") return MeshoptFilter::None;
  if (name == "OCTAHEDRAL") return MeshoptFilter::Octahedral;
  if (name == "QUATERNION") return MeshoptFilter::Quaternion;
  if (name == "EXPONENTIAL") return MeshoptFilter::Exponential;
  throw SceneError(file,
                   what + ": unknown filter '" + name + "' (expected NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
}

// The extension object of bufferViews[index], checked against the rules the spec lists
// under "JSON schema updates". They are also what meshoptimizer's decoders assert.
MeshoptView read_view(const std::string& file, const json& view, const json& ext, int index) {
  const std::string what = "bufferView " + std::to_string(index) + " " + kExtension;
  if (!ext.is_object()) throw SceneError(file, what + " must be an object");
  MeshoptView v;
  v.view = index;
  const std::size_t buffer = size_property(file, ext, "buffer", true, what);
  if (buffer > std::size_t(INT_MAX)) throw SceneError(file, what + ": buffer index out of range");
  v.buffer = int(buffer);
  v.byte_offset = size_property(file, ext, "byteOffset", false, what);
  v.byte_length = size_property(file, ext, "byteLength", true, what);
  v.byte_stride = size_property(file, ext, "byteStride", true, what);
  v.count = size_property(file, ext, "count", true, what);
  v.mode = mode_of(file, string_property(file, ext, "mode", nullptr, what), what);
  v.filter = filter_of(file, string_property(file, ext, "filter", "NONE", what), what);

  const std::size_t stride = v.byte_stride;
  const std::string stride_text = "byteStride " + std::to_string(stride);
  if (v.count == 0) throw SceneError(file, what + ": count must be at least 1");
  if (v.mode == MeshoptMode::Attributes && (stride == 0 || stride % 4 != 0 || stride > 256))
    throw SceneError(file, what + ": " + stride_text + " must be a multiple of 4 up to 256 for mode ATTRIBUTES");
  if (v.mode != MeshoptMode::Attributes) {
    if (stride != 2 && stride != 4)
      throw SceneError(file, what + ": " + stride_text + " must be 2 or 4 for index modes");
    if (v.filter != MeshoptFilter::None) throw SceneError(file, what + ": index modes take no filter");
  }
  if (v.mode == MeshoptMode::Triangles && v.count % 3 != 0)
    throw SceneError(file, what + ": count " + std::to_string(v.count) + " is not a multiple of 3 (mode TRIANGLES)");
  if (v.filter == MeshoptFilter::Octahedral && stride != 4 && stride != 8)
    throw SceneError(file, what + ": " + stride_text + " must be 4 or 8 for filter OCTAHEDRAL");
  if (v.filter == MeshoptFilter::Quaternion && stride != 8)
    throw SceneError(file, what + ": " + stride_text + " must be 8 for filter QUATERNION");

  // The parent bufferView describes the decoded data.
  const std::size_t parent_stride =
      size_property(file, view, "byteStride", false, "bufferView " + std::to_string(index));
  if (parent_stride != 0 && parent_stride != stride)
    throw SceneError(
        file, what + ": " + stride_text + " differs from the bufferView's byteStride " + std::to_string(parent_stride));
  const std::size_t parent_length =
      size_property(file, view, "byteLength", true, "bufferView " + std::to_string(index));
  std::size_t decoded = 0;
  if (__builtin_mul_overflow(v.count, stride, &decoded) || decoded != parent_length)
    throw SceneError(file, what + ": count " + std::to_string(v.count) + " times " + stride_text +
                               " is not the bufferView's byteLength " + std::to_string(parent_length));
  return v;
}

// The most decoded bytes `v`'s compressed bytes can hold, from the bitstreams (spec,
// Appendix A): ATTRIBUTES spends at least 2 header bits per byte of a group of 16 elements
// (16 * stride bytes from stride / 4 bytes: 64 to 1), TRIANGLES at least one code byte per
// triangle, INDICES at least one byte per index.
std::size_t decoded_capacity(const MeshoptView& v) {
  switch (v.mode) {
    case MeshoptMode::Attributes:
      return 64 * v.byte_length;
    case MeshoptMode::Triangles:
      return 3 * v.byte_stride * v.byte_length;
    case MeshoptMode::Indices:
      return v.byte_stride * v.byte_length;
  }
  return 0;
}

// meshoptimizer's decoders return 0, or -1 / -2 / -3 (the same codes in 0.18's vertex and
// index decoders, checked against its encoder's output).
std::string decode_failure(int code) {
  switch (code) {
    case -1:
      return "unknown header or bitstream version";
    case -2:
      return "the data ends early or is corrupt";
    case -3:
      return "bytes are left over after the last element";
    default:
      return "error " + std::to_string(code);
  }
}

}  // namespace

MeshoptPlan plan_meshopt(const std::string& file, std::string_view json_text) {
  MeshoptPlan plan;
  // A cheap look first: most files never name the extension.
  if (json_text.find(kExtension) == std::string_view::npos) return plan;
  json doc = json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (!doc.is_object() || !doc.contains("bufferViews") || !doc["bufferViews"].is_array()) return plan;
  const json& views = doc["bufferViews"];
  const std::size_t buffer_count = doc.contains("buffers") && doc["buffers"].is_array() ? doc["buffers"].size() : 0;
  // Per buffer: views referring to it, those of them compressed, and whether an extension
  // object takes compressed bytes from it.
  std::vector<std::size_t> refs(buffer_count, 0), compressed_refs(buffer_count, 0);
  std::vector<bool> source(buffer_count, false);
  for (std::size_t i = 0; i < views.size() && i <= std::size_t(INT_MAX); ++i) {
    const json& view = views[i];
    if (!view.is_object()) continue;  // refused by check_gltf_json
    const json* ext = extension_of(view);
    if (ext) plan.views.push_back(read_view(file, view, *ext, int(i)));
    const auto buffer = view.find("buffer");
    if (buffer != view.end() && buffer->is_number_unsigned() && buffer->get<std::uint64_t>() < buffer_count) {
      ++refs[buffer->get<std::size_t>()];
      if (ext) ++compressed_refs[buffer->get<std::size_t>()];
    }
    if (ext && std::size_t(plan.views.back().buffer) < buffer_count)
      source[std::size_t(plan.views.back().buffer)] = true;
  }

  bool changed = false;
  for (std::size_t b = 0; b < buffer_count; ++b) {
    json& buffer = doc["buffers"][b];
    if (!buffer.is_object() || compressed_refs[b] != refs[b] || source[b]) continue;
    const json* ext = extension_of(buffer);
    const bool fallback = ext && ext->is_object() && ext->contains("fallback") && (*ext)["fallback"] == true;
    if (!fallback && (refs[b] == 0 || buffer.contains("uri"))) continue;
    // Three zero bytes: tinygltf refuses an empty data URI.
    buffer["uri"] = "data:application/octet-stream;base64,AAAA";
    buffer["byteLength"] = 3;
    changed = true;
  }
  if (changed) plan.json = doc.dump();
  return plan;
}

void decode_meshopt(const std::vector<MeshoptView>& views, tinygltf::Model& model, const std::string& file) {
  // Every size is checked before anything is allocated: one compressed range may back many
  // views, each of which would decode.
  const std::size_t file_buffers = model.buffers.size();  // decoded views get buffers after these
  std::size_t total = 0;
  for (const MeshoptView& v : views) {
    const std::string what = "bufferView " + std::to_string(v.view) + " " + kExtension;
    if (v.view < 0 || std::size_t(v.view) >= model.bufferViews.size())
      throw SceneError(file, what + ": bufferView index out of range");
    if (std::size_t(v.buffer) >= file_buffers)
      throw SceneError(file, what + ": buffer index " + std::to_string(v.buffer) + " out of range (the file has " +
                                 std::to_string(file_buffers) + " buffers)");
    const std::size_t available = model.buffers[std::size_t(v.buffer)].data.size();
    std::size_t end = 0;
    if (__builtin_add_overflow(v.byte_offset, v.byte_length, &end) || end > available)
      throw SceneError(file, what + ": the compressed data (offset " + std::to_string(v.byte_offset) + ", length " +
                                 std::to_string(v.byte_length) + ") runs past the end of buffer " +
                                 std::to_string(v.buffer) + " (" + std::to_string(available) + " bytes)");
    const std::size_t size = v.count * v.byte_stride;  // no overflow: plan_meshopt checked it
    if (size > decoded_capacity(v))
      throw SceneError(file, what + ": " + std::to_string(v.byte_length) + " bytes of compressed data cannot hold " +
                                 std::to_string(v.count) + " elements of " + std::to_string(v.byte_stride) + " bytes");
    if (size > kMaxMeshoptDecodedBytes - total)
      throw SceneError(file, what + ": the file's compressed bufferViews decode to more than the limit of " +
                                 std::to_string(kMaxMeshoptDecodedBytes) + " bytes");
    total += size;
  }

  for (const MeshoptView& v : views) {
    const std::string what = "bufferView " + std::to_string(v.view) + " " + kExtension;
    const std::size_t size = v.count * v.byte_stride;
    std::vector<unsigned char> decoded(size);
    const unsigned char* bytes = model.buffers[std::size_t(v.buffer)].data.data() + v.byte_offset;
    int status = 0;
    switch (v.mode) {
      case MeshoptMode::Attributes:
        status = meshopt_decodeVertexBuffer(decoded.data(), v.count, v.byte_stride, bytes, v.byte_length);
        break;
      case MeshoptMode::Triangles:
        status = meshopt_decodeIndexBuffer(decoded.data(), v.count, v.byte_stride, bytes, v.byte_length);
        break;
      case MeshoptMode::Indices:
        status = meshopt_decodeIndexSequence(decoded.data(), v.count, v.byte_stride, bytes, v.byte_length);
        break;
    }
    if (status != 0) throw SceneError(file, what + ": the data does not decode: " + decode_failure(status));
    switch (v.filter) {
      case MeshoptFilter::None:
        break;
      case MeshoptFilter::Octahedral:
        meshopt_decodeFilterOct(decoded.data(), v.count, v.byte_stride);
        break;
      case MeshoptFilter::Quaternion:
        meshopt_decodeFilterQuat(decoded.data(), v.count, v.byte_stride);
        break;
      case MeshoptFilter::Exponential:
        meshopt_decodeFilterExp(decoded.data(), v.count, v.byte_stride);
        break;
    }

    tinygltf::Buffer buffer;
    buffer.name = what + " (decoded)";
    buffer.data = std::move(decoded);
    model.buffers.push_back(std::move(buffer));  // `bytes` is not used past here
    tinygltf::BufferView& view = model.bufferViews[std::size_t(v.view)];
    view.buffer = int(model.buffers.size() - 1);
    view.byteOffset = 0;
    view.byteLength = size;
  }
}

}  // namespace lancer::gltf
