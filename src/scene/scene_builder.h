// Appends triangles to a Scene with the checks every reader needs: non-finite positions
// are refused, zero-area triangles are dropped and counted, and per-corner attributes
// are kept aligned with the triangle arrays.
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"

namespace lancer {

struct CornerAttributes {
  const glm::vec3* normals = nullptr;    // 3 entries or null
  const glm::vec2* texcoords = nullptr;  // 3 entries or null
  const glm::vec4* tangents = nullptr;   // 3 entries or null
  const glm::vec2* texcoords1 = nullptr; // 3 entries or null (TEXCOORD_1)
  const glm::vec4* colors = nullptr;     // 3 entries or null (COLOR_0, linear RGBA)
};

class SceneBuilder {
 public:
  // `file` is used in error messages.
  SceneBuilder(Scene& scene, std::string file) : scene_(scene), file_(std::move(file)) {}

  // Adds one world-space triangle. `source_id` is its position among the file's
  // triangles. Throws SceneError on a NaN or infinite position. Returns false (and
  // counts it) when the triangle has zero area and is dropped.
  bool add_triangle(const glm::vec3 p[3], std::uint32_t material, std::uint32_t source_id,
                    const CornerAttributes& attribs = {});

  // Makes room for `triangles` more triangles, growing by at least half the capacity so
  // that many small calls stay linear. Readers call it with a count they have checked
  // against the data (never with a count a file merely claims): one big mesh is then
  // stored without the doubling that would briefly need three times its size.
  void reserve_more(std::size_t triangles);

  // Drops spare capacity, adds the default material if the scene has none, and checks
  // material ids.
  void finish();

 private:
  Scene& scene_;
  std::string file_;
};

}  // namespace lancer
