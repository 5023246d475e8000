#include "scene/gltf_skins.h"

#include <tiny_gltf.h>

#include <cmath>
#include <string>

#include "scene/scene_error.h"

namespace lancer::gltf {

std::vector<glm::dmat4> joint_matrices(const ModelRef& m, int skin, const std::vector<glm::dmat4>& worlds) {
  const auto& skins = m.model.skins;
  if (skin < 0 || std::size_t(skin) >= skins.size())
    throw SceneError(m.file, "skin index " + std::to_string(skin) + " out of range (the file has " +
                                 std::to_string(skins.size()) + " skins)");
  const tinygltf::Skin& s = skins[std::size_t(skin)];
  const std::string what = "skin " + std::to_string(skin);
  if (s.joints.empty()) throw SceneError(m.file, what + " has no joints");
  std::vector<glm::mat4> inverse_bind;
  if (s.inverseBindMatrices >= 0) {
    inverse_bind = read_mat4_floats(m, s.inverseBindMatrices, what + " inverseBindMatrices");
    if (inverse_bind.size() < s.joints.size())
      throw SceneError(m.file, what + " has " + std::to_string(s.joints.size()) + " joints but " +
                                   std::to_string(inverse_bind.size()) + " inverseBindMatrices");
  }
  std::vector<glm::dmat4> out;
  out.reserve(s.joints.size());
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const int node = s.joints[j];
    if (node < 0 || std::size_t(node) >= worlds.size())
      throw SceneError(m.file, what + " joint " + std::to_string(j) + ": node index " + std::to_string(node) +
                                   " out of range (the file has " + std::to_string(worlds.size()) + " nodes)");
    const glm::dmat4 joint =
        worlds[std::size_t(node)] * (inverse_bind.empty() ? glm::dmat4(1.0) : glm::dmat4(inverse_bind[j]));
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(joint[c][0] + joint[c][1] + joint[c][2] + joint[c][3]))
        throw SceneError(m.file, what + " joint " + std::to_string(j) + " has a non-finite matrix");
    out.push_back(joint);
  }
  return out;
}

}  // namespace lancer::gltf
