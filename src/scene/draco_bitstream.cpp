#include "scene/draco_bitstream.h"

#include <draco/compression/decode.h>

namespace lancer::draco_io {

namespace {

float integer_max(draco::DataType type) {
  switch (type) {
    case draco::DT_INT8: return 127.0f;
    case draco::DT_UINT8: return 255.0f;
    case draco::DT_INT16: return 32767.0f;
    case draco::DT_UINT16: return 65535.0f;
    default: return 0.0f;
  }
}

bool is_integer(draco::DataType type) {
  return type != draco::DT_FLOAT32 && type != draco::DT_FLOAT64 && type != draco::DT_BOOL;
}

}  // namespace

bool decode_mesh(const unsigned char* data, std::size_t size, Mesh& out, std::string& error) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    error = decoded.status().error_msg_string();
    return false;
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  out = Mesh{};
  out.points = mesh->num_points();
  out.indices.reserve(std::size_t(mesh->num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (const draco::PointIndex& p : mesh->face(f)) {
      if (p.value() >= out.points) {
        error = "a face names a point out of range";
        return false;
      }
      out.indices.push_back(p.value());
    }
  for (int a = 0; a < mesh->num_attributes(); ++a) {
    const draco::PointAttribute& att = *mesh->attribute(a);
    Attribute o;
    o.unique_id = att.unique_id();
    o.components = att.num_components();
    o.integer = is_integer(att.data_type());
    o.normalized = att.normalized();
    o.integer_max = integer_max(att.data_type());
    o.values.assign(std::size_t(out.points) * 4, 0.0f);
    for (draco::PointIndex p(0); p < mesh->num_points(); ++p)
      if (!att.ConvertValue<float>(att.mapped_index(p), 4, &o.values[std::size_t(p.value()) * 4])) {
        error = "attribute " + std::to_string(o.unique_id) + " has a value that cannot be read";
        return false;
      }
    out.attributes.push_back(std::move(o));
  }
  return true;
}

}  // namespace lancer::draco_io
