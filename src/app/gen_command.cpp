#include "app/gen_command.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <new>
#include <ostream>
#include <stdexcept>

#include "scene/gltf_writer.h"
#include "simd/out_of_memory.h"

namespace lancer {

namespace {

bool ends_in_glb(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".glb";
}

}  // namespace

int run_gen(const GenOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    if (opt.kind != "spd") throw std::invalid_argument("unknown generator kind '" + opt.kind + "' (expected spd)");
    if (opt.output.empty()) throw std::invalid_argument("no output file given (-o FILE.glb)");
    if (!ends_in_glb(opt.output))
      throw std::invalid_argument("output '" + opt.output + "' must end in .glb (binary glTF)");
    const Scene scene = make_spd(opt.name, opt.size, opt.tessellation);
    write_glb(scene, opt.output);
    out << "wrote " << opt.output << ": " << scene.triangle_count() << " triangles (spd " << opt.name << ", size "
        << opt.size << ")\n";
    return 0;
  } catch (const std::bad_alloc& e) {
    err << "lancer: error: " << out_of_memory_message(e) << " generating spd " << opt.name << " at size " << opt.size
        << "\n";
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace lancer
