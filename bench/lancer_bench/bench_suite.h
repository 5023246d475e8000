// The scenes lancer-bench measures: the project's built-in scenes (scenes/*.gltf), Haines'
// procedural SPD databases at sizes of 10^4..10^6 triangles, and every OBJ/glTF mesh of a
// models folder; each with the square camera its ray sets start from.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/camera.h"
#include "scene/scene.h"

namespace lancer::bench {

// A scene name lancer-bench does not know (the message lists the ones it does).
struct UnknownScene : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SuiteScene {
  enum class Kind { File, Spd };
  std::string name;    // e.g. "cornell-box", "balls-3", "stanford-bunny"
  std::string origin;  // "built-in", "spd" or "models"
  Kind kind = Kind::File;
  std::filesystem::path file;  // Kind::File
  std::string spd;             // Kind::Spd: generator and size
  int spd_size = 0;
};

// The default suite, in this order: the built-in scenes of `scenes_dir`, the SPD
// databases (balls-3, gears-4, mount-7, rings-5, tetra-8 at the default tessellation), then
// the .obj, .gltf and .glb files of `models_dir` by file name (none when it is empty).
// A model whose name another scene already has is named by its file name instead.
std::vector<SuiteScene> default_suite(const std::filesystem::path& scenes_dir, const std::filesystem::path& models_dir);

// The scenes called `names`, in that order, taken from `suite`; "<spd>-<size>" also names
// an SPD database of any valid size. Throws UnknownScene for any other name.
std::vector<SuiteScene> select_scenes(const std::vector<SuiteScene>& suite, const std::vector<std::string>& names);

struct BenchScene {
  Scene scene;
  PinholeCamera camera;
  bool added_light = false;  // the scene had no light: a point light was added for shadow rays
};

// Loads or generates the scene. The camera is the scene's first camera, else a three-
// quarter view from the front whose image the scene's bounding box just fills; always
// size x size pixels. A scene without any light (no punctual light, no emissive triangle,
// e.g. an OBJ mesh) gets one point light above it and to the left, so that it has shadow
// rays. Throws SceneError or
// std::invalid_argument as the readers and generators do.
BenchScene load_bench_scene(const SuiteScene& entry, int size);

// The suite entry of SPD generator `generator` at `size`, named "<generator>-<size>".
SuiteScene spd_entry(const std::string& generator, int size);

}  // namespace lancer::bench
