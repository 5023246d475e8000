#include "app/rays_command.h"

#include <filesystem>
#include <memory>
#include <new>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/accel_factory.h"
#include "app/camera_choice.h"
#include "app/render_command.h"
#include "render/ray_file.h"
#include "scene/load_scene.h"
#include "simd/out_of_memory.h"

namespace lancer {

int run_rays(const RaysOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    if (opt.output.empty()) throw std::invalid_argument("no output file (-o)");
    const Scene scene = load_scene(opt.scene);
    print_load_warnings(scene, err);
    int height = opt.height;
    // The scene's first camera, or the renderer's default framing camera.
    const PinholeCamera camera = choose_camera(CameraRequest{}, scene, opt.width, height, true);

    std::vector<Ray> rays;
    if (opt.set == RaySet::Primary) {
      rays = primary_rays(camera);
    } else {
      const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", scene.triangles, scene.instancing);
      rays = make_ray_set(scene, *accel, camera, opt.set, opt.seed);
    }
    // A ray file holds at least one ray (read_rays refuses empty files).
    if (rays.empty())
      throw std::invalid_argument("no camera ray hits " + scene.source + ", so the " +
                                  std::string(ray_set_name(opt.set)) + " set is empty");

    const std::filesystem::path parent = std::filesystem::path(opt.output).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    write_rays(opt.output, rays);
    out << "lancer rays: " << rays.size() << " " << ray_set_name(opt.set) << " rays (" << opt.width << "x" << height
        << " pixels, seed " << opt.seed << ") to " << opt.output << "\n";
    return 0;
  } catch (const std::bad_alloc& e) {
    err << "lancer: error: " << out_of_memory_message(e) << "\n";
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace lancer
