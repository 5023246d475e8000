// libFuzzer target for the OBJ + MTL reader. The input is the OBJ text, optionally
// followed by a line "#mtl" and the text of input.mtl; both are written to a scratch
// folder (the reader takes a path and opens `mtllib` files next to the OBJ), so an input
// reaches the MTL parser by saying `mtllib input.mtl`.
// A SceneError is the expected answer to bad input; anything else (a crash, a sanitizer
// report, another exception, a scene that breaks fuzz_support.h's checks) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "fuzz_support.h"
#include "scene/obj_reader.h"
#include "scene/scene_error.h"

namespace {

constexpr std::string_view kMtlSeparator = "\n#mtl\n";

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  lancer::fuzz::mute_std_cerr();
  (void)lancer::fuzz::scratch_dir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  // memmem rather than string_view::find: libFuzzer watches memmem's arguments and so
  // learns the separator by itself.
  const void* found = size ? ::memmem(input.data(), input.size(), kMtlSeparator.data(), kMtlSeparator.size()) : nullptr;
  const std::size_t split = found ? std::size_t(static_cast<const char*>(found) - input.data()) : input.size();
  const std::string_view obj = input.substr(0, split);
  const std::string_view mtl = found ? input.substr(split + kMtlSeparator.size()) : std::string_view();

  const std::filesystem::path obj_path = lancer::fuzz::scratch_dir() / "input.obj";
  const std::filesystem::path mtl_path = lancer::fuzz::scratch_dir() / "input.mtl";
  lancer::fuzz::write_file(obj_path, obj);
  if (found) {
    lancer::fuzz::write_file(mtl_path, mtl);
  } else {
    std::error_code ec;
    std::filesystem::remove(mtl_path, ec);
  }
  try {
    lancer::fuzz::check_scene(lancer::read_obj(obj_path));
  } catch (const lancer::SceneError&) {
  }
  return 0;
}
