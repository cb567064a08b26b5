#include "core/scene/scene_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include "core/scene/scene_summary.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/shipped_data.h"

namespace mtg::scene {
namespace {

using ::testing::HasSubstr;
using testing::FixtureDataset;

double yaw_of(const Eigen::Isometry3d& X) {
  const Eigen::Vector3d x = X.linear().col(0);
  return std::atan2(x.y(), x.x());
}

Scene load_fixture(const FixtureDataset& fx, const std::string& name, int jobs = 1) {
  MeshCache cache;
  return load_scene(index_dataset(fx.root()), name, cache, {.jobs = jobs});
}

TEST(LoadScene, PoseIsConvertedFromYupToZup) {
  FixtureDataset fx;
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.2, 0.1, 0.4}));
  fx.add_scene("s", {{"object_instances",
                      {FixtureDataset::instance("toy_box", {1.0, 0.5, -2.0}, 90.0)}}});
  const Scene scene = load_fixture(fx, "s");
  ASSERT_EQ(scene.objects.size(), 1u);
  const ObjectInstance& o = scene.objects[0];
  EXPECT_EQ(o.name, "toy_box_0");
  // (x, y, z)_habitat -> (x, -z, y)_zup; a +90 deg yaw about Habitat's +Y is +90 deg about +Z.
  EXPECT_TRUE(o.X_WO.translation().isApprox(Eigen::Vector3d(1.0, 2.0, 0.5), 1e-12));
  EXPECT_NEAR(yaw_of(o.X_WO), M_PI / 2, 1e-9);
  // The 0.4 m (asset z) side now runs along world x after the yaw; height 0.1 stays vertical.
  const Eigen::AlignedBox3d b = o.world_bounds();
  EXPECT_NEAR(b.sizes().x(), 0.4, 1e-6);
  EXPECT_NEAR(b.sizes().y(), 0.2, 1e-6);
  EXPECT_NEAR(b.min().z(), 0.5, 1e-6);
  EXPECT_NEAR(b.max().z(), 0.6, 1e-6);
}

TEST(LoadScene, UniformScaleAndReceptaclesAreApplied) {
  FixtureDataset fx;
  nlohmann::json extra;
  extra["user_defined"]["receptacle_aabb_top"] = {{"position", {0.0, 0.6, 0.0}},
                                                  {"scale", {0.4, 0.1, 0.3}}};
  fx.add_object_config("toy_table", fx.add_box_mesh("table", {1.0, 0.5, 0.8}), extra);
  auto inst = FixtureDataset::instance("toy_table", {0, 0, 0});
  inst["uniform_scale"] = 2.0;
  fx.add_scene("s", {{"object_instances", {inst}}});
  const Scene scene = load_fixture(fx, "s");
  const ObjectInstance& o = scene.objects.at(0);
  EXPECT_NEAR(o.world_bounds().max().z(), 1.0, 1e-6);
  ASSERT_EQ(o.receptacles.size(), 1u);
  const DeclaredReceptacle& r = o.receptacles[0];
  // Half extents: y in [0.5, 0.7] in R, scaled by 2 and turned Z-up.
  const Eigen::Vector3d lo = r.T_OR * r.box_R.min();
  EXPECT_NEAR(lo.z(), 1.0, 1e-9);
  EXPECT_NEAR((r.T_OR * r.box_R.max()).z(), 1.4, 1e-9);
}

TEST(LoadScene, MalformedSceneJsonNamesFileAndLine) {
  FixtureDataset fx;
  fx.write_text("configs/scenes/broken.scene_instance.json", "{\n  \"object_instances\": [\n  }\n");
  try {
    load_fixture(fx, "broken");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("broken.scene_instance.json: invalid JSON at line 3"));
  }
}

TEST(LoadScene, BadFieldNamesItsJsonPath) {
  FixtureDataset fx;
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.2, 0.1, 0.4}));
  auto inst = FixtureDataset::instance("toy_box", {0, 0, 0});
  inst["rotation"] = {1.0, 0.0, 0.0};
  fx.add_scene("s", {{"object_instances", {inst}}});
  try {
    load_fixture(fx, "s");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.scene_instance.json: /object_instances/0/rotation: "
                                    "expected an array of 4 numbers"));
  }
}

TEST(LoadScene, AnAbsurdTranslationNamesItsFileAndField) {
  FixtureDataset fx;
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.2, 0.1, 0.4}));
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("toy_box", {0, 0, 0}),
                                           FixtureDataset::instance("toy_box", {1e308, 0, 0})}}});
  try {
    load_fixture(fx, "s");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.scene_instance.json: /object_instances/1/translation: "
                                    "a position more than 10000 m from the origin"));
  }
}

TEST(LoadScene, MissingAndBrokenMeshesWarnOnceAndFallBack) {
  FixtureDataset fx;
  nlohmann::json with_collision;
  with_collision["collision_asset"] = fx.add_box_mesh("hull", {0.2, 0.2, 0.2});
  fx.add_object_config("toy_missing", "../../objects/nowhere.glb", with_collision);
  fx.add_object_config("toy_broken", fx.add_raw_file("broken.glb", "glTF garbage bytes"));
  fx.add_scene("s", {{"object_instances",
                      {FixtureDataset::instance("toy_missing", {0, 0, 0}),
                       FixtureDataset::instance("toy_missing", {1, 0, 0}),
                       FixtureDataset::instance("toy_broken", {2, 0, 0})}}});
  for (const int jobs : {1, 3}) {  // meshes read on several threads first: the same warnings, once
    const Scene scene = load_fixture(fx, "s", jobs);
    ASSERT_EQ(scene.objects.size(), 3u);
    EXPECT_EQ(scene.stats.meshes_missing, 2);
    ASSERT_EQ(scene.warnings.size(), 3u) << ::testing::PrintToString(scene.warnings);
    EXPECT_THAT(scene.warnings[0], HasSubstr("mesh missing for missing_0"));
    EXPECT_THAT(scene.warnings[0], HasSubstr("nowhere.glb"));
    EXPECT_THAT(scene.warnings[1], HasSubstr("broken mesh for broken_2"));
    EXPECT_THAT(scene.warnings[2], HasSubstr("object broken_2: no geometry at all"));
    // The missing render mesh falls back to the collision asset.
    EXPECT_FALSE(scene.objects[0].parts[0].render);
    EXPECT_TRUE(scene.objects[0].parts[0].collision);
    EXPECT_NEAR(scene.objects[0].world_bounds().sizes().z(), 0.2, 1e-6);
  }
}

TEST(LoadScene, UnknownTemplateAndBrokenUrdfAreSkippedWithAWarning) {
  FixtureDataset fx;
  fx.write_text("urdf/bad/bad.urdf", "<robot name='x'><link name='a'><joint></robot>");
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("nobody", {0, 0, 0})}},
                     {"articulated_object_instances",
                      {{{"template_name", "bad"}, {"translation", {0, 0, 0}}}}}});
  const Scene scene = load_fixture(fx, "s");
  EXPECT_TRUE(scene.objects.empty());
  ASSERT_EQ(scene.warnings.size(), 2u);
  // Named by file and place in it, so a typo in a template name is found where it was made.
  EXPECT_THAT(scene.warnings[0], HasSubstr("s.scene_instance.json: /object_instances/0: object nobody_0: "
                                           "no object config for template 'nobody'"));
  EXPECT_THAT(scene.warnings[1], HasSubstr("bad.urdf: URDF does not parse, skipped"));
}

// ---- the shipped ReplicaCAD apartments ----

const Scene& shipped(const std::string& name) {
  static std::map<std::string, Scene> scenes;
  static MeshCache cache(MeshLoadOptions{.keep_textures = false});
  auto it = scenes.find(name);
  if (it == scenes.end()) {
    it = scenes.emplace(name, load_scene(*testing::shipped_dataset(), name, cache)).first;
  }
  return it->second;
}

TEST(LoadSceneShipped, InstanceCountsMatchTheSceneFiles) {
  MTG_REQUIRE_SHIPPED_DATA();
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    const nlohmann::json doc = read_json_file(testing::shipped_dataset()->scene_file(name));
    const std::size_t rigid = doc["object_instances"].size();
    const std::size_t articulated = doc["articulated_object_instances"].size();
    const Scene& scene = shipped(name);
    EXPECT_EQ(scene.objects.size(), rigid + articulated) << name;
    int n_articulated = 0;
    for (const auto& o : scene.objects) n_articulated += o.articulated ? 1 : 0;
    EXPECT_EQ(n_articulated, static_cast<int>(articulated)) << name;
    // The only problems in the shipped copy are the meshes its NOTICE says were removed.
    for (const auto& w : scene.warnings) EXPECT_THAT(w, HasSubstr("mesh missing")) << name;
  }
}

TEST(LoadSceneShipped, ArticulatedObjectsAndTheirReceptaclesHaveGeometry) {
  MTG_REQUIRE_SHIPPED_DATA();
  const std::map<std::string, std::size_t> receptacles = {
      {"fridge", 5}, {"kitchen_counter", 10}, {"kitchenCupboard_01", 12},
      {"chestOfDrawers_01", 0}, {"cabinet", 0}, {"door2", 0}};
  int seen = 0;
  for (const ObjectInstance& o : shipped("apt_0").objects) {
    if (!o.articulated) continue;
    ++seen;
    EXPECT_EQ(o.receptacles.size(), receptacles.at(o.template_name)) << o.name;
    EXPECT_GT(o.render_triangles(), 100u) << o.name;
    for (const DeclaredReceptacle& r : o.receptacles) {
      ASSERT_LT(static_cast<std::size_t>(r.part), o.parts.size());
      // Every receptacle box lies inside (or touches) its object's world bounds.
      Eigen::AlignedBox3d box_W;
      for (int c = 0; c < 8; ++c) {
        box_W.extend(o.X_WO * (r.T_OR * r.box_R.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))));
      }
      const Eigen::AlignedBox3d bounds = o.world_bounds();
      EXPECT_TRUE(bounds.intersects(box_W)) << o.name << " " << r.name;
    }
  }
  EXPECT_EQ(seen, 6);
  // The fridge stands upright: 1.92 m tall (Z-up), bottom near the floor.
  const ObjectInstance* fridge = shipped("apt_0").find("fridge_0");
  ASSERT_NE(fridge, nullptr);
  EXPECT_NEAR(fridge->world_bounds().sizes().z(), 1.92, 0.03);
  EXPECT_NEAR(fridge->world_bounds().min().z(), 0.0, 0.03);
}

TEST(LoadSceneShipped, BasketPoseMatchesAHandComputation) {
  MTG_REQUIRE_SHIPPED_DATA();
  // apt_0 object_instances[0]: translation [-1.99566, 1.08394, 0.05798] (Y-up),
  // rotation [w x y z] = [0.98470, ~0, 0.17429, ~0]: a yaw of 2 atan2(0.17429, 0.98470)
  // = 20.07 deg about +Y, i.e. about +Z after the conversion (x, y, z) -> (x, -z, y).
  const ObjectInstance* basket = shipped("apt_0").find("basket_0");
  ASSERT_NE(basket, nullptr);
  EXPECT_NEAR(basket->X_WO.translation().x(), -1.9956579525706273, 1e-9);
  EXPECT_NEAR(basket->X_WO.translation().y(), -0.057981376432922185, 1e-9);
  EXPECT_NEAR(basket->X_WO.translation().z(), 1.0839370509764081, 1e-9);
  EXPECT_NEAR(yaw_of(basket->X_WO) * 180.0 / M_PI, 20.07, 0.01);
  EXPECT_NEAR(basket->X_WO.linear()(2, 2), 1.0, 1e-6);  // upright
  EXPECT_EQ(basket->category, "basket");
}

TEST(LoadSceneShipped, EveryObjectStandsOnOrAboveTheFloor) {
  MTG_REQUIRE_SHIPPED_DATA();
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    for (const ObjectInstance& o : shipped(name).objects) {
      const Eigen::AlignedBox3d b = o.world_bounds();
      ASSERT_FALSE(b.isEmpty()) << name << " " << o.name;
      // Rugs dip 1 cm into the floor and the door frame 4 cm; nothing more.
      EXPECT_GE(b.min().z(), -0.05) << name << " " << o.name;
      EXPECT_LT(b.max().z(), 3.0) << name << " " << o.name;
    }
  }
}

// scripts/gpu-bundle copies a scene by this list: a dataset holding only the listed files (linked
// from the shipped one) must load the same scene, down to the meshes and semantic classes.
TEST(LoadSceneShipped, ACopyOfTheFilesToCopyLoadsTheSameScene) {
  MTG_REQUIRE_SHIPPED_DATA();
  const Dataset& shipped_ds = *testing::shipped_dataset();
  const Scene& original = shipped("apt_0");
  const std::vector<std::filesystem::path> files = files_to_copy(shipped_ds, original);
  FixtureDataset copy;  // an empty temporary root
  for (const std::filesystem::path& f : files) {
    const std::filesystem::path to = copy.root() / f.lexically_relative(shipped_ds.root);
    std::filesystem::create_directories(to.parent_path());
    std::filesystem::create_symlink(f, to);
  }
  const Dataset copied_ds = index_dataset(copy.root());
  MeshCache cache(MeshLoadOptions{.keep_textures = false});
  const Scene copied = load_scene(copied_ds, "apt_0", cache);
  EXPECT_EQ(copied_ds.semantic_classes, shipped_ds.semantic_classes);
  EXPECT_EQ(copied.stats.meshes_loaded, original.stats.meshes_loaded);
  EXPECT_EQ(copied.stats.meshes_missing, original.stats.meshes_missing);
  EXPECT_EQ(summarize_scene(copied)["triangles"], summarize_scene(original)["triangles"]);
  EXPECT_EQ(copied.warnings.size(), original.warnings.size());
  ASSERT_EQ(copied.objects.size(), original.objects.size());
  for (std::size_t i = 0; i < copied.objects.size(); ++i) {
    EXPECT_EQ(copied.objects[i].name, original.objects[i].name);
    EXPECT_EQ(copied.objects[i].parts.size(), original.objects[i].parts.size()) << copied.objects[i].name;
  }
  // Nothing the dataset does not need: an absent mesh stays off the list.
  for (const std::filesystem::path& f : files) EXPECT_TRUE(std::filesystem::is_regular_file(f)) << f;
  EXPECT_LT(files.size(), original.source_files.size() + shipped_ds.config_files.size());
}

// Meshes read on several threads before the scene is put together give the scene one thread gives.
TEST(LoadSceneShipped, MeshesReadOnSeveralThreadsGiveTheSameScene) {
  MTG_REQUIRE_SHIPPED_DATA();
  const Scene& one = shipped("apt_0");
  MeshCache cache(MeshLoadOptions{.keep_textures = false});
  const Scene many = load_scene(*testing::shipped_dataset(), "apt_0", cache, {.jobs = 3});
  EXPECT_EQ(many.warnings, one.warnings);
  EXPECT_EQ(many.stats.meshes_loaded, one.stats.meshes_loaded);
  EXPECT_EQ(many.stats.meshes_missing, one.stats.meshes_missing);
  EXPECT_EQ(many.source_files, one.source_files);
  EXPECT_EQ(summarize_scene(many), [&] {
    nlohmann::json j = summarize_scene(one);
    j["load_ms"] = summarize_scene(many)["load_ms"];  // telemetry
    return j;
  }());
}

}  // namespace
}  // namespace mtg::scene
