#include "scene/gltf_animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "scene/animation_sampling.h"

#include "scene/gltf_accessors.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer::gltf {

namespace {

struct NodePose {
  int node = -1;
  std::string path;
  std::vector<double> values;
  double first_key = 0.0, last_key = 0.0;  // the channel's keyframe times
};

// The value channel `c` of animation 0 gives its node at `time`.
NodePose sample(const ModelRef& m, const tinygltf::Animation& a, std::size_t c, double time) {
  const tinygltf::AnimationChannel& ch = a.channels[c];
  const std::string what = "animation 0 channel " + std::to_string(c);
  NodePose pose;
  pose.node = ch.target_node;
  pose.path = ch.target_path;
  if (ch.sampler < 0 || std::size_t(ch.sampler) >= a.samplers.size())
    throw SceneError(m.file, what + ": sampler index " + std::to_string(ch.sampler) + " out of range");
  const tinygltf::AnimationSampler& s = a.samplers[std::size_t(ch.sampler)];
  const bool cubic = s.interpolation == "CUBICSPLINE";
  if (!cubic && s.interpolation != "LINEAR" && s.interpolation != "STEP")
    throw SceneError(m.file, what + ": unknown interpolation '" + s.interpolation + "'");
  const std::vector<float> times = read_animation_times(m, s.input, what + " input");
  const std::size_t keys = times.size();
  if (keys == 0) throw SceneError(m.file, what + ": the sampler has no keyframes");
  for (std::size_t k = 0; k < keys; ++k)
    if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
      throw SceneError(m.file, what + ": keyframe time " + std::to_string(k) + " (" + std::to_string(times[k]) +
                                   ") is not finite or not after the one before (glTF: times increase)");
  pose.first_key = times.front();
  pose.last_key = times.back();
  ChannelKeys channel;
  channel.times = times;
  channel.interpolation =
      cubic ? Interpolation::CubicSpline : s.interpolation == "STEP" ? Interpolation::Step : Interpolation::Linear;
  std::vector<double> values;
  auto at_time = [&](std::size_t width) {
    channel.values = values;
    channel.width = width;
    return sample_channel(channel, time);
  };
  const std::size_t per_key = cubic ? 3 : 1;  // CUBICSPLINE: in-tangent, value, out-tangent
  auto check_count = [&](std::size_t outputs, std::size_t width) {
    if (outputs != keys * per_key * width)
      throw SceneError(m.file, what + ": the output has " + std::to_string(outputs) + " elements, expected " +
                                   std::to_string(keys * per_key * width) + " for " + std::to_string(keys) +
                                   " keyframe(s)");
  };
  if (pose.path == "translation" || pose.path == "scale") {
    const std::vector<glm::vec3> out = read_animation_vec3(m, s.output, what + " output");
    check_count(out.size(), 1);
    for (const glm::vec3& v : out) values.insert(values.end(), {v.x, v.y, v.z});
    pose.values = at_time(3);
  } else if (pose.path == "rotation") {
    const std::vector<glm::vec4> out = read_rotations(m, s.output, what + " output");
    check_count(out.size(), 1);
    for (const glm::vec4& q : out) values.insert(values.end(), {q.x, q.y, q.z, q.w});
    channel.rotation = true;
    pose.values = at_time(4);
  } else if (pose.path == "weights") {
    const std::vector<float> out = read_animation_weights(m, s.output, what + " output");
    const std::size_t targets = out.size() / (keys * per_key);
    check_count(out.size(), targets);
    values.assign(out.begin(), out.end());
    pose.values = targets > 0 ? at_time(targets) : std::vector<double>{};
  } else {
    pose.path.clear();  // "pointer" (KHR_animation_pointer) and others: not a node's pose
  }
  return pose;
}

}  // namespace

AnimationRange pose_animation(tinygltf::Model& model, const std::string& file, std::optional<double> time,
                              bool warn) {
  AnimationRange range;
  range.animations = model.animations.size();
  if (model.animations.empty()) {
    if (time && warn) print_scene_warnings(file, "the file has no animation: --frame-time changes nothing");
    return range;
  }
  const ModelRef m{model, file};
  const tinygltf::Animation& a = model.animations[0];
  if (model.animations.size() > 1 && warn)
    print_scene_warnings(file, std::to_string(model.animations.size() - 1) +
                                   " animation(s) after the first ignored: the scene is posed by animation 0");
  // Read every channel before changing any node. Without a time, each channel's first
  // keyframe: every time before it holds that value.
  const double t = time.value_or(-std::numeric_limits<double>::infinity());
  std::vector<NodePose> poses;
  for (std::size_t c = 0; c < a.channels.size(); ++c) poses.push_back(sample(m, a, c, t));
  range.channels = poses.size();
  for (std::size_t c = 0; c < poses.size(); ++c) {
    range.start = c == 0 ? poses[c].first_key : std::min(range.start, poses[c].first_key);
    range.end = c == 0 ? poses[c].last_key : std::max(range.end, poses[c].last_key);
  }
  for (std::size_t c = 0; c < poses.size(); ++c) {
    const NodePose& p = poses[c];
    if (p.path.empty()) continue;
    if (p.node < 0 || std::size_t(p.node) >= model.nodes.size())
      throw SceneError(file, "animation 0 channel " + std::to_string(c) + ": target node " + std::to_string(p.node) +
                                 " out of range (the file has " + std::to_string(model.nodes.size()) + " nodes)");
    tinygltf::Node& node = model.nodes[std::size_t(p.node)];
    if (p.path == "weights") {
      node.weights = p.values;
      continue;
    }
    if (!node.matrix.empty()) {
      if (warn)
        print_scene_warnings(file, "animation 0 channel " + std::to_string(c) + " animates node " +
                                     std::to_string(p.node) + ", which has a matrix (glTF forbids it): channel ignored");
      continue;
    }
    (p.path == "translation" ? node.translation : p.path == "rotation" ? node.rotation : node.scale) = p.values;
  }
  return range;
}

}  // namespace lancer::gltf
