#include "app/info_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <ostream>

#include "accel/accel_factory.h"
#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "app/render_command.h"
#include "scene/load_scene.h"
#include "simd/out_of_memory.h"
#include "simd/process_memory.h"

namespace lancer {

int run_info(const InfoOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    const Scene scene = load_scene(opt.scene, opt.gltf_scene, std::nullopt, opt.instancing);
    const Bounds3 b = scene.bounds();
    std::size_t emissive = 0;
    for (std::uint32_t id : scene.material_id) emissive += scene.materials[id].emissive() ? 1 : 0;

    char line[256];
    out << "scene:      " << scene.source << "\n";
    out << "triangles:  " << scene.triangle_count() << " (" << emissive << " emissive)\n";
    if (!scene.instancing.empty())
      out << "instances:  " << scene.instancing.instances.size() << " of " << scene.instancing.meshes.size()
          << " meshes, " << scene.drawn_triangle_count() << " triangles drawn\n";
    out << "dropped:    " << scene.stats.degenerate_dropped << " zero-area\n";
    out << "materials:  " << scene.materials.size() << "\n";
    out << "textures:   " << scene.textures.size() << " (" << scene.images.size() << " images)\n";
    out << "cameras:    " << scene.cameras.size() << "\n";
    out << "lights:     " << scene.lights.size() << " punctual\n";
    if (scene.animation.animations == 0) {
      out << "animation:  none\n";
    } else {
      std::snprintf(line, sizeof line,
                    "animation:  %zu (the first: %zu channel(s), keyframes from %g to %g s; --frame-time poses it)\n",
                    scene.animation.animations, scene.animation.channels, scene.animation.start, scene.animation.end);
      out << line;
    }
    std::snprintf(line, sizeof line, "bounds:     (%g, %g, %g) - (%g, %g, %g)\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x,
                  b.hi.y, b.hi.z);
    out << line;
    // What the reader warned about: what the file uses that the render will ignore.
    out << "warnings:   " << scene.warnings.size() << (scene.warnings.empty() ? "\n" : " (ignored or changed)\n");
    constexpr std::size_t kListed = 20;
    for (std::size_t i = 0; i < scene.warnings.size() && i < kListed; ++i) out << "  - " << scene.warnings[i] << "\n";
    if (scene.warnings.size() > kListed) out << "  ... and " << scene.warnings.size() - kListed << " more\n";

    const auto t0 = std::chrono::steady_clock::now();
    const std::unique_ptr<Accelerator> accel =
        make_accelerator(opt.accel, scene.triangles, scene.instancing, kd_options_from(opt.kd_split), isa_from(opt.isa));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (const auto* kd = dynamic_cast<const KdTree*>(accel.get())) {
      out << "accel:      kdtree (" << opt.kd_split << "), isa " << isa_name(kd->isa()) << "\n";
      print_kd_stats(out, compute_kd_stats(*kd));
    } else {
      std::snprintf(line, sizeof line, "accel:      %s, built in %.1f ms, %zu bytes\n",
                    std::string(accel->name()).c_str(), ms, accel->memory_bytes());
      out << line;
    }
    // What loading and building took at their peak, the whole process counted.
    if (const std::int64_t peak = peak_resident_bytes(); peak > 0) {
      std::snprintf(line, sizeof line, "peak memory: %.1f MiB resident (%.1f bytes per triangle)\n",
                    static_cast<double>(peak) / (1024.0 * 1024.0),
                    static_cast<double>(peak) / static_cast<double>(scene.triangle_count()));
      out << line;
    }
    return 0;
  } catch (const std::bad_alloc& e) {
    err << "lancer: error: " << out_of_memory_message(e) << "\n";
    return 1;
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace lancer
