#include "draco_test_encoder.h"

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <stdexcept>

namespace lancer::test {

DracoEncoded draco_encode(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                          const std::vector<glm::vec2>& uvs, const std::vector<std::uint32_t>& indices) {
  const int faces = static_cast<int>(indices.size() / 3);
  draco::TriangleSoupMeshBuilder soup;
  soup.Start(faces);
  const int pos = soup.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nrm = soup.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  const int uv = soup.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f) {
    const std::uint32_t* c = &indices[3 * std::size_t(f)];
    soup.SetAttributeValuesForFace(pos, draco::FaceIndex(f), &positions[c[0]], &positions[c[1]], &positions[c[2]]);
    soup.SetAttributeValuesForFace(nrm, draco::FaceIndex(f), &normals[c[0]], &normals[c[1]], &normals[c[2]]);
    soup.SetAttributeValuesForFace(uv, draco::FaceIndex(f), &uvs[c[0]], &uvs[c[1]], &uvs[c[2]]);
  }
  const std::unique_ptr<draco::Mesh> mesh = soup.Finalize();
  if (!mesh) throw std::runtime_error("Draco could not build the mesh");
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
  if (!status.ok()) throw std::runtime_error("Draco could not encode the mesh: " + status.error_msg_string());
  DracoEncoded out;
  out.bytes.assign(buffer.data(), buffer.data() + buffer.size());
  out.points = mesh->num_points();
  out.position_id = mesh->attribute(pos)->unique_id();
  out.normal_id = mesh->attribute(nrm)->unique_id();
  out.texcoord_id = mesh->attribute(uv)->unique_id();
  return out;
}

}  // namespace lancer::test
