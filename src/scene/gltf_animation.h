// A glTF file's animation reduced to one pose: Lancer renders a still (the motion issue
// adds time), and a file that animates its nodes is shown in the pose its first animation
// starts from, not in the rest pose its nodes store.
#pragma once

#include <string>

namespace tinygltf {
class Model;
}

namespace lancer::gltf {

// Overwrites the translation, rotation, scale and morph weights of every node that
// model.animations[0] animates with that channel's value at its first keyframe (glTF 2.0,
// "Animations": times increase, so keyframe 0; a CUBICSPLINE sampler stores in-tangent,
// value and out-tangent per keyframe, so its value is the second element). Other
// animations are ignored, with a warning. A channel that targets a node with a matrix
// (which glTF forbids) is skipped with a warning. Throws SceneError for a malformed
// channel or sampler.
void pose_at_first_frame(tinygltf::Model& model, const std::string& file);

}  // namespace lancer::gltf
