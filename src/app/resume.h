// `lancer render --resume FILE.exr`: what a checkpoint must match for the resumed render to
// end with the image an uninterrupted render gives, bit for bit.
#pragma once

#include <string>

#include "app/render_command.h"
#include "render/camera.h"
#include "render/checkpoint_file.h"
#include "scene/scene.h"

namespace lancer {

// The facts a render's EXR records: every setting that changes its image (size, integrator,
// seed, max depth, light samples, filter, the camera as placed, the environment), a hash of
// the scene (scene_fingerprint), the program version, and the spp target ("spp", the only
// one a resume may change). `settings` and `camera` are the render's, after every default.
CheckpointFacts render_facts(const RenderOptions& options, const RenderSettings& settings, const Scene& scene,
                             const PinholeCamera& camera);

// A hash of what a scene was made from: the scene file's bytes (a .glb's binary chunk
// included), an OBJ's mtllib files, and what the reader made of external buffers and images
// (the triangles with their per-corner attributes, the lights, the decoded images' pixels).
std::string scene_fingerprint(const std::string& file, const Scene& scene);

// Throws std::invalid_argument when `checkpoint` (read from `file`) was rendered otherwise
// than `now` says, naming the first difference; "spp" may differ.
void check_resumable(const Checkpoint& checkpoint, const CheckpointFacts& now, const std::string& file);

// For --resume FILE: checks `checkpoint` against this render (check_resumable, `facts` gets
// this render's), goes on to the checkpoint's spp target when the command line gives neither
// --spp nor --time (refused when that was `open_spp`: a --time render's), refuses a
// checkpoint with more samples than settings.spp, and returns the state to continue from.
RenderState take_resumed_state(Checkpoint checkpoint, const RenderOptions& options, RenderSettings& settings,
                               const Scene& scene, const PinholeCamera& camera, int open_spp, CheckpointFacts& facts);

}  // namespace lancer
