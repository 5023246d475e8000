#include "scene/gltf_json_checks.h"

#include <array>
#include <climits>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <nlohmann/json.hpp>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

using nlohmann::json;

// What a property must be. Index: a glTF id, an integer in [0, INT_MAX] (tinygltf
// stores ids as int and would silently wrap larger ones). Size: a byte count, offset
// or element count, any non-negative integer (bounds are checked on use).
enum class Kind { Index, Size, Integer, Number, Bool, String, Object, NumberArray, IndexArray, StringArray };

struct Field {
  const char* key;
  Kind kind;
};

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::Index:
      return "a non-negative integer (an index)";
    case Kind::Size:
      return "a non-negative integer";
    case Kind::Integer:
      return "an integer";
    case Kind::Number:
      return "a number";
    case Kind::Bool:
      return "a boolean";
    case Kind::String:
      return "a string";
    case Kind::Object:
      return "an object";
    case Kind::NumberArray:
      return "an array of numbers";
    case Kind::IndexArray:
      return "an array of non-negative integers";
    case Kind::StringArray:
      return "an array of strings";
  }
  return "?";
}

bool is_index(const json& v) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>() <= std::uint64_t(INT_MAX);
  if (v.is_number_integer()) return v.get<std::int64_t>() >= 0 && v.get<std::int64_t>() <= INT_MAX;
  return false;
}

bool all_of(const json& v, bool (*pred)(const json&)) {
  if (!v.is_array()) return false;
  for (const json& e : v)
    if (!pred(e)) return false;
  return true;
}

bool matches(const json& v, Kind kind) {
  switch (kind) {
    case Kind::Index:
      return is_index(v);
    case Kind::Size:
      return v.is_number_unsigned() || (v.is_number_integer() && v.get<std::int64_t>() >= 0);
    case Kind::Integer:
      return v.is_number_integer();
    case Kind::Number:
      return v.is_number();
    case Kind::Bool:
      return v.is_boolean();
    case Kind::String:
      return v.is_string();
    case Kind::Object:
      return v.is_object();
    case Kind::NumberArray:
      return all_of(v, [](const json& e) { return e.is_number(); });
    case Kind::IndexArray:
      return all_of(v, is_index);
    case Kind::StringArray:
      return all_of(v, [](const json& e) { return e.is_string(); });
  }
  return false;
}

class Checker {
 public:
  explicit Checker(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw SceneError(file_, "wrong JSON type: " + path + " " + what);
  }

  // Each listed property, when present, must have its kind.
  void fields(const json& obj, const std::string& path, std::initializer_list<Field> list) const {
    for (const Field& f : list) {
      const auto it = obj.find(f.key);
      if (it != obj.end() && !matches(*it, f.kind))
        fail(path + "." + f.key, std::string("must be ") + kind_name(f.kind));
    }
  }

  // Calls `each(element, path)` for every element of the array obj[key], which must
  // hold objects. Absent arrays are fine unless `required`.
  template <typename Fn>
  void objects(const json& obj, const std::string& path, const char* key, bool required, Fn each) const {
    const std::string here = path.empty() ? std::string(key) : path + "." + key;
    const auto it = obj.find(key);
    if (it == obj.end()) {
      if (required) throw SceneError(file_, "missing property: " + here);
      return;
    }
    if (!it->is_array()) fail(here, "must be an array");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const std::string at = here + "[" + std::to_string(i) + "]";
      if (!(*it)[i].is_object()) fail(at, "must be an object");
      each((*it)[i], at);
    }
  }

  // obj[key], when present, must be an object; then `each(child, path)` checks it.
  template <typename Fn>
  void object(const json& obj, const std::string& path, const char* key, Fn each) const {
    const auto it = obj.find(key);
    if (it == obj.end()) return;
    const std::string here = path + "." + key;
    if (!it->is_object()) fail(here, "must be an object");
    each(*it, here);
  }

  void texture_info(const json& obj, const std::string& path, const char* key) const {
    object(obj, path, key, [&](const json& t, const std::string& p) {
      fields(t, p,
             {{"index", Kind::Index}, {"texCoord", Kind::Index}, {"scale", Kind::Number}, {"strength", Kind::Number}});
    });
  }

 private:
  const std::string& file_;
};

void check_extensions_required(const std::string& file, const json& doc) {
  const auto it = doc.find("extensionsRequired");
  if (it == doc.end()) return;
  for (const json& name : *it) {
    const std::string ext = name.get<std::string>();
    if (!extension_supported(ext))
      throw SceneError(file, "required glTF extension '" + ext + "' is not supported by Lancer");
  }
}

void check_document(const Checker& c, const json& doc) {
  c.fields(doc, "(root)",
           {{"scene", Kind::Index},
            {"extensionsRequired", Kind::StringArray},
            {"extensionsUsed", Kind::StringArray},
            {"asset", Kind::Object}});
  c.objects(doc, "", "scenes", false, [&](const json& s, const std::string& p) {
    c.fields(s, p, {{"nodes", Kind::IndexArray}});
  });
  c.objects(doc, "", "nodes", false, [&](const json& n, const std::string& p) {
    c.fields(n, p,
             {{"mesh", Kind::Index},
              {"camera", Kind::Index},
              {"skin", Kind::Index},
              {"children", Kind::IndexArray},
              {"matrix", Kind::NumberArray},
              {"translation", Kind::NumberArray},
              {"rotation", Kind::NumberArray},
              {"scale", Kind::NumberArray}});
    c.object(n, p, "extensions", [&](const json& e, const std::string& ep) {
      c.object(e, ep, "KHR_lights_punctual", [&](const json& l, const std::string& lp) {
        c.fields(l, lp, {{"light", Kind::Index}});
      });
    });
  });
  c.objects(doc, "", "meshes", false, [&](const json& m, const std::string& p) {
    c.objects(m, p, "primitives", true, [&](const json& prim, const std::string& pp) {
      c.fields(prim, pp, {{"indices", Kind::Index}, {"material", Kind::Index}, {"mode", Kind::Integer}});
      const auto attrs = prim.find("attributes");
      if (attrs == prim.end()) return;  // refused earlier in check_gltf_json
      if (!attrs->is_object()) c.fail(pp + ".attributes", "must be an object");
      for (auto a = attrs->begin(); a != attrs->end(); ++a)
        if (!is_index(a.value())) c.fail(pp + ".attributes." + a.key(), "must be a non-negative integer");
    });
  });
  c.objects(doc, "", "accessors", false, [&](const json& a, const std::string& p) {
    c.fields(a, p,
             {{"bufferView", Kind::Index},
              {"byteOffset", Kind::Size},
              {"count", Kind::Size},
              {"componentType", Kind::Index},
              {"normalized", Kind::Bool},
              {"type", Kind::String}});
    c.object(a, p, "sparse", [&](const json& s, const std::string& sp) {
      c.fields(s, sp, {{"count", Kind::Index}});  // tinygltf holds it in an int
      c.object(s, sp, "indices", [&](const json& i, const std::string& ip) {
        c.fields(
            i, ip,
            {{"bufferView", Kind::Index}, {"byteOffset", Kind::Index}, {"componentType", Kind::Index}});  // int too
      });
      c.object(s, sp, "values", [&](const json& v, const std::string& vp) {
        c.fields(v, vp, {{"bufferView", Kind::Index}, {"byteOffset", Kind::Index}});
      });
    });
  });
  c.objects(doc, "", "bufferViews", false, [&](const json& v, const std::string& p) {
    c.fields(
        v, p,
        {{"buffer", Kind::Index}, {"byteOffset", Kind::Size}, {"byteLength", Kind::Size}, {"byteStride", Kind::Size}});
    c.object(v, p, "extensions", [&](const json& e, const std::string& ep) {
      c.object(e, ep, "EXT_meshopt_compression", [&](const json& m, const std::string& mp) {
        c.fields(m, mp,
                 {{"buffer", Kind::Index},
                  {"byteOffset", Kind::Size},
                  {"byteLength", Kind::Size},
                  {"byteStride", Kind::Size},
                  {"count", Kind::Size},
                  {"mode", Kind::String},
                  {"filter", Kind::String}});
      });
    });
  });
  c.objects(doc, "", "buffers", false, [&](const json& b, const std::string& p) {
    c.fields(b, p, {{"byteLength", Kind::Size}, {"uri", Kind::String}});
    c.object(b, p, "extensions", [&](const json& e, const std::string& ep) {
      c.object(e, ep, "EXT_meshopt_compression", [&](const json& m, const std::string& mp) {
        c.fields(m, mp, {{"fallback", Kind::Bool}});
      });
    });
  });
  c.objects(doc, "", "materials", false, [&](const json& m, const std::string& p) {
    c.fields(m, p,
             {{"alphaMode", Kind::String},
              {"alphaCutoff", Kind::Number},
              {"doubleSided", Kind::Bool},
              {"emissiveFactor", Kind::NumberArray}});
    c.object(m, p, "pbrMetallicRoughness", [&](const json& pbr, const std::string& pp) {
      c.fields(pbr, pp,
               {{"baseColorFactor", Kind::NumberArray},
                {"metallicFactor", Kind::Number},
                {"roughnessFactor", Kind::Number}});
      c.texture_info(pbr, pp, "baseColorTexture");
      c.texture_info(pbr, pp, "metallicRoughnessTexture");
    });
    c.texture_info(m, p, "normalTexture");
    c.texture_info(m, p, "occlusionTexture");
    c.texture_info(m, p, "emissiveTexture");
  });
  c.objects(doc, "", "textures", false, [&](const json& t, const std::string& p) {
    c.fields(t, p, {{"sampler", Kind::Index}, {"source", Kind::Index}});
    c.object(t, p, "extensions", [&](const json& e, const std::string& ep) {
      c.object(e, ep, "EXT_texture_webp", [&](const json& w, const std::string& wp) {
        c.fields(w, wp, {{"source", Kind::Index}});
      });
    });
  });
  c.objects(doc, "", "samplers", false, [&](const json& s, const std::string& p) {
    c.fields(s, p,
             {{"wrapS", Kind::Index}, {"wrapT", Kind::Index}, {"magFilter", Kind::Index}, {"minFilter", Kind::Index}});
  });
  c.objects(doc, "", "images", false, [&](const json& i, const std::string& p) {
    c.fields(i, p, {{"bufferView", Kind::Index}, {"uri", Kind::String}, {"mimeType", Kind::String}});
  });
  c.objects(doc, "", "cameras", false, [&](const json& cam, const std::string& p) {
    c.fields(cam, p, {{"type", Kind::String}});
  });
  c.object(doc, "(root)", "extensions", [&](const json& e, const std::string& ep) {
    c.object(e, ep, "KHR_lights_punctual", [&](const json& k, const std::string& kp) {
      c.objects(k, kp, "lights", false, [&](const json& l, const std::string& lp) {
        c.fields(l, lp,
                 {{"type", Kind::String},
                  {"color", Kind::NumberArray},
                  {"intensity", Kind::Number},
                  {"range", Kind::Number},
                  {"spot", Kind::Object}});
        c.object(l, lp, "spot", [&](const json& s, const std::string& sp) {
          c.fields(s, sp, {{"innerConeAngle", Kind::Number}, {"outerConeAngle", Kind::Number}});
        });
      });
    });
  });
}

// Deeply nested JSON (in extras, say) would make tinygltf's recursive conversion of
// extras/extensions overflow the stack; no real glTF nests anywhere near this deep.
constexpr int kMaxJsonDepth = 128;

void check_nesting(const std::string& file, std::string_view text) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw SceneError(file, "invalid glTF: JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

std::uint32_t read_u32(const unsigned char* p) {
  // glTF binary is little-endian (GLB spec, section "Binary glTF Layout").
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

}  // namespace

bool extension_supported(std::string_view name) {
  static constexpr std::array<std::string_view, 16> kSupported = {
      "KHR_lights_punctual",    "KHR_materials_emissive_strength", "KHR_materials_ior",   "KHR_materials_transmission",
      "KHR_materials_specular", "KHR_texture_transform",           "KHR_materials_volume", "KHR_mesh_quantization",
      "EXT_mesh_gpu_instancing", "KHR_draco_mesh_compression",     "KHR_materials_clearcoat",
      "KHR_materials_sheen",    "KHR_materials_unlit",             "KHR_materials_pbrSpecularGlossiness",
      "EXT_meshopt_compression", "EXT_texture_webp"};
  for (std::string_view s : kSupported)
    if (s == name) return true;
  return false;
}

void check_gltf_json(const std::string& file, std::string_view json_text) {
  check_nesting(file, json_text);
  json doc;
  try {
    doc = json::parse(json_text.begin(), json_text.end());
  } catch (const json::exception& e) {
    throw SceneError(file, std::string("invalid JSON: ") + e.what());
  }
  if (!doc.is_object()) throw SceneError(file, "invalid glTF: the JSON root is not an object");
  const Checker checker(file);
  checker.fields(doc, "(root)", {{"extensionsRequired", Kind::StringArray}});
  // Refuse unsupported required extensions first: their data may break other checks.
  check_extensions_required(file, doc);
  // A primitive with no attributes is dropped by tinygltf without a word: refuse it.
  if (const auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array())
    for (std::size_t m = 0; m < meshes->size(); ++m) {
      const json& mesh = (*meshes)[m];
      if (!mesh.is_object()) continue;  // reported by check_document
      const auto prims = mesh.find("primitives");
      if (prims == mesh.end() || !prims->is_array()) continue;
      for (std::size_t p = 0; p < prims->size(); ++p)
        if ((*prims)[p].is_object() && !(*prims)[p].contains("attributes"))
          throw SceneError(file, "missing property: meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) +
                                     "].attributes");
    }
  check_document(checker, doc);
}

std::string_view glb_json_chunk(const std::string& file, std::span<const unsigned char> bytes) {
  // Layout (glTF 2.0 spec, "GLB File Format Specification"): a 12-byte header (magic
  // "glTF", version 2, total length), then chunks of (length, type, data); the first
  // chunk is JSON (type 0x4E4F534A), an optional second one BIN.
  const std::size_t size = bytes.size();
  if (size < 12)
    throw SceneError(file, "truncated binary glTF: " + std::to_string(size) + " bytes, less than the 12-byte header");
  if (std::memcmp(bytes.data(), "glTF", 4) != 0) throw SceneError(file, "not a binary glTF file (bad magic)");
  const std::uint32_t version = read_u32(bytes.data() + 4);
  if (version != 2) throw SceneError(file, "unsupported binary glTF version " + std::to_string(version));
  const std::uint64_t length = read_u32(bytes.data() + 8);
  if (length > size)
    throw SceneError(file, "truncated binary glTF: the header declares " + std::to_string(length) +
                               " bytes but the file has " + std::to_string(size));
  if (length < 20) throw SceneError(file, "truncated binary glTF: no room for the JSON chunk header");
  const std::uint64_t json_length = read_u32(bytes.data() + 12);
  const std::uint32_t json_type = read_u32(bytes.data() + 16);
  if (json_type != 0x4E4F534Au) throw SceneError(file, "malformed binary glTF: the first chunk is not JSON");
  if (20 + json_length > length)
    throw SceneError(file, "truncated binary glTF: the JSON chunk runs past the end of the file");
  // The chunk after it (BIN), when a chunk header follows: tinygltf reads the length it
  // declares without checking it against the data it was given (a heap over-read found by
  // fuzzing), so a chunk that runs past the end is refused here.
  const std::uint64_t next = 20 + json_length;
  if (next + 8 <= length) {
    const std::uint64_t chunk_length = read_u32(bytes.data() + next);
    if (next + 8 + chunk_length > length)
      throw SceneError(file, "truncated binary glTF: the chunk after the JSON chunk declares " +
                                 std::to_string(chunk_length) + " bytes but only " +
                                 std::to_string(length - next - 8) + " follow its header");
  }
  return std::string_view(reinterpret_cast<const char*>(bytes.data() + 20), json_length);
}

}  // namespace lancer::gltf
