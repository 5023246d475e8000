// A shading point whose shading normal leans away from the geometric one, and views around
// it: what the tests of the wedge between the two tangent planes (shading_inputs.h) build.
#pragma once

#include <cmath>
#include <numbers>

#include <glm/vec3.hpp>

#include "render/shading_inputs.h"

namespace lancer::test {

// ng = +z, ns leaning `lean_degrees` toward +x, a white material of `roughness`.
inline ShadingInputs leaning_point(float lean_degrees, float roughness, float metallic, float transmission = 0.0f) {
  ShadingInputs si;
  const float lean = lean_degrees * std::numbers::pi_v<float> / 180.0f;
  si.ng = {0, 0, 1};
  si.ns = {std::sin(lean), 0, std::cos(lean)};
  si.tangent = {std::cos(lean), 0, -std::sin(lean)};
  si.base_color = glm::vec3(1.0f);
  si.roughness = roughness;
  si.metallic = metallic;
  si.transmission = transmission;
  return si;
}

// A unit direction `degrees` off ng toward +x (the side ns leans to).
inline glm::vec3 view(float degrees) {
  const float a = degrees * std::numbers::pi_v<float> / 180.0f;
  return {std::sin(a), 0.0f, std::cos(a)};
}

}  // namespace lancer::test
