// glTF reader: the thin-lens convention in a camera's extras,
// {"aperture": radius, "focusDistance": distance}.
#include <gtest/gtest.h>

#include <string>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

class CameraLensExtras : public gltf_test::GltfTempDir {
 protected:
  // One perspective camera with the given extras (omitted when null), read back.
  Scene read_with_extras(const json& extras) {
    GltfBuilder b;
    json camera = {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}};
    if (!extras.is_null()) camera["extras"] = extras;
    b.push("cameras", camera);
    b.set_scene({b.add_node({{"camera", 0}})});
    b.write_data_uri_gltf(path("lens.gltf"));
    return read_gltf(path("lens.gltf"));
  }

  void expect_refused(const json& extras, const std::string& key) {
    try {
      read_with_extras(extras);
      ADD_FAILURE() << "accepted extras " << extras.dump();
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("lens.gltf"), std::string::npos) << what;
      EXPECT_NE(what.find("camera 0"), std::string::npos) << what;
      EXPECT_NE(what.find("extras." + key), std::string::npos) << what;
    }
  }
};

TEST_F(CameraLensExtras, ApertureAndFocusDistanceAreRead) {
  const Scene s = read_with_extras({{"aperture", 0.025}, {"focusDistance", 3.5}, {"other", "kept apart"}});
  ASSERT_EQ(s.cameras.size(), 1u);
  ASSERT_TRUE(s.cameras[0].aperture_radius.has_value());
  ASSERT_TRUE(s.cameras[0].focus_distance.has_value());
  EXPECT_FLOAT_EQ(*s.cameras[0].aperture_radius, 0.025f);
  EXPECT_FLOAT_EQ(*s.cameras[0].focus_distance, 3.5f);
}

TEST_F(CameraLensExtras, EachFieldIsOptional) {
  const Scene none = read_with_extras(nullptr);
  ASSERT_EQ(none.cameras.size(), 1u);
  EXPECT_FALSE(none.cameras[0].aperture_radius.has_value());
  EXPECT_FALSE(none.cameras[0].focus_distance.has_value());

  const Scene aperture_only = read_with_extras({{"aperture", 0}});
  ASSERT_TRUE(aperture_only.cameras[0].aperture_radius.has_value());
  EXPECT_EQ(*aperture_only.cameras[0].aperture_radius, 0.0f) << "a zero aperture is a pinhole, and allowed";
  EXPECT_FALSE(aperture_only.cameras[0].focus_distance.has_value());

  const Scene focus_only = read_with_extras({{"focusDistance", 2}});
  EXPECT_FALSE(focus_only.cameras[0].aperture_radius.has_value());
  ASSERT_TRUE(focus_only.cameras[0].focus_distance.has_value());
  EXPECT_FLOAT_EQ(*focus_only.cameras[0].focus_distance, 2.0f);

  // Extras that are not an object belong to some other tool: ignored.
  const Scene other = read_with_extras("a note from another exporter");
  EXPECT_FALSE(other.cameras[0].aperture_radius.has_value());
}

TEST_F(CameraLensExtras, BadValuesAreRefusedWithTheirName) {
  expect_refused({{"aperture", -0.1}}, "aperture");
  expect_refused({{"aperture", "wide"}}, "aperture");
  expect_refused({{"aperture", 1e300}}, "aperture");
  expect_refused({{"focusDistance", 0}}, "focusDistance");
  expect_refused({{"focusDistance", -2.0}}, "focusDistance");
  expect_refused({{"aperture", 0.1}, {"focusDistance", json::array({1, 2})}}, "focusDistance");
}

}  // namespace
}  // namespace lancer
