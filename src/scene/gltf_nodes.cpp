#include "scene/gltf_nodes.h"

#include <tiny_gltf.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <utility>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

std::string node_name(int node) { return "node " + std::to_string(node); }

// glTF 2.0 spec, "Transformations": a node has either a column-major matrix or
// T * R * S, with R a unit quaternion stored (x, y, z, w).
glm::dmat4 local_transform(const ModelRef& m, int index) {
  const tinygltf::Node& n = m.model.nodes[std::size_t(index)];
  const std::string what = node_name(index);
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16)
      throw SceneError(m.file, what + ": matrix has " + std::to_string(n.matrix.size()) + " numbers, not 16");
    return glm::make_mat4(n.matrix.data());
  }
  auto check_size = [&](const std::vector<double>& v, std::size_t size, const char* key) {
    if (!v.empty() && v.size() != size)
      throw SceneError(
          m.file, what + ": " + key + " has " + std::to_string(v.size()) + " numbers, not " + std::to_string(size));
  };
  check_size(n.translation, 3, "translation");
  check_size(n.rotation, 4, "rotation");
  check_size(n.scale, 3, "scale");
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (!n.translation.empty())
    t = glm::translate(glm::dmat4(1.0), glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (!n.rotation.empty()) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glm takes (w, x, y, z)
    const double len = glm::length(q);
    if (!(len > 0.0) || !std::isfinite(len))
      throw SceneError(m.file, what + ": rotation quaternion has zero or non-finite length");
    r = glm::mat4_cast(q / len);
  }
  if (!n.scale.empty()) s = glm::scale(glm::dmat4(1.0), glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return t * r * s;
}

// parent[i] for every node, -1 for roots; refuses out-of-range children, nodes with
// two parents and cycles.
std::vector<int> parents_of(const ModelRef& m) {
  const std::size_t count = m.model.nodes.size();
  std::vector<int> parent(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    for (int c : m.model.nodes[i].children) {
      if (c < 0 || std::size_t(c) >= count)
        throw SceneError(m.file, node_name(int(i)) + ": child index " + std::to_string(c) +
                                     " out of range (the file has " + std::to_string(count) + " nodes)");
      if (std::size_t(c) == i)
        throw SceneError(m.file, "node hierarchy has a cycle: node " + std::to_string(c) + " is its own child");
      if (parent[std::size_t(c)] != -1)
        throw SceneError(m.file, "node hierarchy is not a tree: node " + std::to_string(c) +
                                     " is a child of both node " + std::to_string(parent[std::size_t(c)]) +
                                     " and node " + std::to_string(i));
      parent[std::size_t(c)] = int(i);
    }
  }
  // With at most one parent each, a node is reachable from a root unless it lies on
  // (or below) a cycle.
  std::vector<char> reached(count, 0);
  std::vector<int> stack;
  for (std::size_t i = 0; i < count; ++i)
    if (parent[i] == -1) stack.push_back(int(i));
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    reached[std::size_t(n)] = 1;
    for (int c : m.model.nodes[std::size_t(n)].children) stack.push_back(c);
  }
  for (std::size_t i = 0; i < count; ++i)
    if (!reached[i]) throw SceneError(m.file, "node hierarchy has a cycle through node " + std::to_string(i));
  return parent;
}

std::vector<int> root_nodes(const ModelRef& m, const std::vector<int>& parent) {
  const auto& scenes = m.model.scenes;
  if (m.model.defaultScene >= 0 && std::size_t(m.model.defaultScene) >= scenes.size())
    throw SceneError(m.file, "default scene " + std::to_string(m.model.defaultScene) + " out of range (the file has " +
                                 std::to_string(scenes.size()) + " scenes)");
  if (m.scene >= 0 && std::size_t(m.scene) >= scenes.size())
    throw SceneError(m.file, "--scene " + std::to_string(m.scene) + ": the file has " + std::to_string(scenes.size()) +
                                 " scene(s)");
  std::vector<int> roots;
  if (scenes.empty()) {
    for (std::size_t i = 0; i < parent.size(); ++i)
      if (parent[i] == -1) roots.push_back(int(i));
    return roots;
  }
  const int chosen = m.scene >= 0 ? m.scene : m.model.defaultScene >= 0 ? m.model.defaultScene : 0;
  const std::string what = "scene " + std::to_string(chosen);
  std::vector<char> listed(parent.size(), 0);
  for (int n : scenes[std::size_t(chosen)].nodes) {
    if (n < 0 || std::size_t(n) >= parent.size())
      throw SceneError(m.file, what + ": node index " + std::to_string(n) + " out of range (the file has " +
                                   std::to_string(parent.size()) + " nodes)");
    if (parent[std::size_t(n)] != -1)
      throw SceneError(m.file, what + " lists node " + std::to_string(n) + ", which is a child of node " +
                                   std::to_string(parent[std::size_t(n)]) + " (scene nodes must be roots)");
    if (listed[std::size_t(n)]) throw SceneError(m.file, what + " lists node " + std::to_string(n) + " twice");
    listed[std::size_t(n)] = 1;
    roots.push_back(n);
  }
  return roots;
}

}  // namespace

std::vector<NodeInstance> scene_nodes(const ModelRef& m) {
  const std::vector<int> parent = parents_of(m);
  const std::vector<int> roots = root_nodes(m, parent);
  // An explicit stack: a deep chain of nodes must not overflow the call stack. Each
  // node is visited once, since the hierarchy was shown to be a forest above.
  std::vector<NodeInstance> order;
  std::vector<std::pair<int, glm::dmat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, glm::dmat4(1.0));
  while (!stack.empty()) {
    const auto [node, parent_world] = stack.back();
    stack.pop_back();
    const glm::dmat4 world = parent_world * local_transform(m, node);
    order.push_back({node, world});
    const std::vector<int>& children = m.model.nodes[std::size_t(node)].children;
    for (auto it = children.rbegin(); it != children.rend(); ++it) stack.emplace_back(*it, world);
  }
  return order;
}

std::vector<glm::dmat4> node_worlds(const ModelRef& m) {
  const std::vector<int> parent = parents_of(m);
  std::vector<glm::dmat4> world(parent.size(), glm::dmat4(1.0));
  std::vector<int> stack;
  for (std::size_t i = 0; i < parent.size(); ++i)
    if (parent[i] == -1) stack.push_back(int(i));
  while (!stack.empty()) {
    const int node = stack.back();
    stack.pop_back();
    const int up = parent[std::size_t(node)];
    world[std::size_t(node)] = (up >= 0 ? world[std::size_t(up)] : glm::dmat4(1.0)) * local_transform(m, node);
    for (int c : m.model.nodes[std::size_t(node)].children) stack.push_back(c);
  }
  return world;
}

}  // namespace lancer::gltf
