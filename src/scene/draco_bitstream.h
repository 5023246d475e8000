// Draco mesh bitstreams, decoded by Google's Draco library behind an interface of our own.
//
// Why a wall: Debian's libdraco carries its own copy of tinygltf (a different version),
// exporting the same symbols as libtinygltf. Linked beside libtinygltf into one binary,
// whichever comes first on the link line wins, and Lancer's glTF reader then runs code
// built for another layout of tinygltf's structs (measured: a heap corruption on every
// glTF load). So only this translation unit includes Draco, built as its own shared
// library (lancer_draco) that depends on libdraco: the executables' own dependencies,
// libtinygltf among them, come first in the loader's search order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lancer::draco_io {

struct Attribute {
  std::uint32_t unique_id = 0;
  int components = 0;        // 1 to 4
  bool integer = false;      // stored as integers
  bool normalized = false;   // Draco's own flag: its integers are already mapped to [0, 1] / [-1, 1]
  float integer_max = 0.0f;  // the largest value of the integer type, for normalising (0: not 8 or 16 bits)
  std::vector<float> values;  // four per point, missing components 0
};

struct Mesh {
  std::uint32_t points = 0;
  std::vector<std::uint32_t> indices;  // three per triangle, each < points
  std::vector<Attribute> attributes;
};

// Decodes the Draco mesh in [data, data + size). False, with the decoder's message in
// `error`, when it does not decode.
bool decode_mesh(const unsigned char* data, std::size_t size, Mesh& out, std::string& error);

}  // namespace lancer::draco_io
