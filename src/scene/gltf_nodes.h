// The glTF node hierarchy: validation and world transforms.
#pragma once

#include <glm/mat4x4.hpp>
#include <vector>

#include "scene/gltf_accessors.h"

namespace lancer::gltf {

struct NodeInstance {
  int node = -1;
  glm::dmat4 world{1.0};  // node space to world space
};

// The nodes of the scene to load, in depth-first pre-order with children in array
// order, each with its world matrix. The scene is m.scene when set (--scene), else the
// file's default scene when set, else scene 0,
// else (no scenes) every root node in index order. Throws SceneError when a child or
// scene index is out of range, a node has two parents, the hierarchy has a cycle, or
// a node's matrix/TRS is malformed: glTF requires the hierarchy to be a forest.
std::vector<NodeInstance> scene_nodes(const ModelRef& m);

// The world matrix of every node of the file, in or out of the scene (skins may name
// joints anywhere), indexed by node. Throws as scene_nodes does.
std::vector<glm::dmat4> node_worlds(const ModelRef& m);

}  // namespace lancer::gltf
