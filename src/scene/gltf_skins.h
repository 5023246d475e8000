// glTF skins: the joint matrices that pose a skinned mesh (glTF 2.0, "Skins").
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/gltf_accessors.h"

namespace lancer::gltf {

// world(joint j) * inverseBindMatrix j for every joint of skin `skin`, in the skin's joint
// order, from `worlds` (node_worlds); a skin without inverseBindMatrices has identities.
// Throws SceneError for a skin or joint index out of range, a skin without joints, fewer
// inverse bind matrices than joints, or a non-finite matrix. (Debian's tinygltf 2.7
// refuses a skin without inverseBindMatrices before this is reached, although the spec
// makes them optional.)
std::vector<glm::dmat4> joint_matrices(const ModelRef& m, int skin, const std::vector<glm::dmat4>& worlds);

}  // namespace lancer::gltf
