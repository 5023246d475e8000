// libFuzzer target for the glTF reader: each input is read from memory twice, once as a
// .gltf (JSON, or binary when it starts with the GLB magic) and once as a .glb. Relative
// buffer and image URIs resolve against a scratch folder holding only texture.png.
// A SceneError is the expected answer to bad input; anything else (a crash, a sanitizer
// report, another exception, a scene that breaks fuzz_support.h's checks) is a finding.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_support.h"
#include "scene/gltf_reader.h"
#include "scene/scene_error.h"

namespace {

void read_as(std::span<const unsigned char> bytes, const char* name) {
  try {
    lancer::fuzz::check_scene(lancer::read_gltf_bytes(bytes, lancer::fuzz::scratch_dir() / name));
  } catch (const lancer::SceneError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  lancer::fuzz::mute_std_cerr();
  (void)lancer::fuzz::scratch_dir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const unsigned char> bytes(data, size);
  read_as(bytes, "input.gltf");
  read_as(bytes, "input.glb");
  return 0;
}
