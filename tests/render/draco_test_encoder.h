// Draco encoding for the KHR_draco_mesh_compression tests, in a shared library of its own
// for the reason src/scene/draco_bitstream.h gives.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace lancer::test {

struct DracoEncoded {
  std::vector<unsigned char> bytes;
  std::uint32_t points = 0;
  std::uint32_t position_id = 0, normal_id = 0, texcoord_id = 0;  // the attributes' unique ids
};

// The indexed triangle mesh as a Draco bitstream, without quantization (lossless).
DracoEncoded draco_encode(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                          const std::vector<glm::vec2>& uvs, const std::vector<std::uint32_t>& indices);

}  // namespace lancer::test
