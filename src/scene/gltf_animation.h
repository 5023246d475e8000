// A glTF file's animation reduced to one pose: the scene as its first animation has it at a
// time of its timeline (lancer render --frame-time), or, without a time, at the first
// keyframe of each channel rather than in the rest pose its nodes store.
#pragma once

#include <optional>
#include <string>

#include "scene/scene.h"

namespace tinygltf {
class Model;
}

namespace lancer::gltf {

// Overwrites the translation, rotation, scale and morph weights of every node that
// model.animations[0] animates with that channel's value at `time` (seconds on the
// animation's timeline; nullopt: each channel's first keyframe), sampled as the channel's
// sampler says (animation_sampling.h). Skins then follow their joints, as the reader poses
// them from the nodes. Other animations are ignored, with a warning; a file without
// animation is left as it is (with a warning when a time was given). A channel that targets
// a node with a matrix (which glTF forbids) is skipped with a warning. Throws SceneError for
// a malformed channel or sampler (times not finite or not increasing, outputs that do not
// match the keyframes). Returns the animations' range (scene.h). `warn` false: the same,
// silently (a reader posing the file at several times warns once).
AnimationRange pose_animation(tinygltf::Model& model, const std::string& file, std::optional<double> time,
                              bool warn = true);

}  // namespace lancer::gltf
