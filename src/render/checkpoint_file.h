// A render's exact state in its EXR output, beside the picture, so that `lancer render
// --resume FILE.exr` can continue it and end with the image an uninterrupted render gives.
//
// The file is an ordinary EXR (R, G, B: the mean of each pixel, what viewers show) plus
//   channels  lancer.sumHi.{R,G,B}, lancer.sumLo.{R,G,B} (UINT): the high and low 32 bits
//             of each double sum, exact; lancer.count (UINT): the pixel's samples;
//   ints      lancer.resume (the format, kCheckpointFormat), lancer.passes (full passes done);
//   strings   lancer.<key> for each fact the caller gives (settings, scene hash, program
//             version: whatever a resume must match), and lancer.digest, a hash of all of the
//             above, so a damaged or edited file is refused rather than resumed wrongly.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "render/render_state.h"

namespace lancer {

inline constexpr int kCheckpointFormat = 1;

// key, value; keys are short names ("seed", "width"), without the "lancer." prefix.
using CheckpointFacts = std::vector<std::pair<std::string, std::string>>;

struct Checkpoint {
  RenderState state;
  CheckpointFacts facts;  // sorted by key
};

// Writes state.mean() and the state to `file` (.exr), atomically as write_image does.
// Throws ImageError on failure, std::invalid_argument for an empty state or a reserved key.
void write_checkpoint(const RenderState& state, const CheckpointFacts& facts, const std::filesystem::path& file);

// Reads a file write_checkpoint wrote. Throws ImageError naming the file when it cannot be
// read, has no resume data ("... has no resume data"), is of another format, or is damaged
// (a channel or attribute missing, the digest or the picture disagreeing with the state).
Checkpoint read_checkpoint(const std::filesystem::path& file);

}  // namespace lancer
