#include "core/scene/urdf_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/shipped_data.h"

namespace mtg::scene {
namespace {

using ::testing::HasSubstr;

TEST(NormalizeUrdfVectors, CommasInsideVectorAttributesBecomeSpaces) {
  EXPECT_EQ(normalize_urdf_vector_attributes(R"(<mesh filename="a,b.glb" scale="1, 2, 3"/>)"),
            R"(<mesh filename="a,b.glb" scale="1  2  3"/>)");
  EXPECT_EQ(normalize_urdf_vector_attributes(R"(<box size="0.6 0.1, 0.8"/>)"),
            R"(<box size="0.6 0.1  0.8"/>)");
}

constexpr const char* kTwoLinkUrdf = R"(<?xml version="1.0"?>
<robot name="box_cabinet">
  <link name="root"/>
  <joint name="root_rotation" type="fixed">
    <origin rpy="0 0 0" xyz="0 0.5 0"/>
    <parent link="root"/><child link="body"/>
  </joint>
  <link name="body">
    <visual><geometry><mesh filename="body.obj" scale="1, 1, 1"/></geometry></visual>
    <collision><origin xyz="0 0.1 0"/><geometry><box size="1 0.2 0.5"/></geometry></collision>
  </link>
  <joint name="door_hinge" type="revolute">
    <origin xyz="0.5 0 0.25"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="2" effort="1" velocity="1"/>
    <parent link="body"/><child link="door"/>
  </joint>
  <link name="door">
    <visual><geometry><mesh filename="door.obj" scale="1, 1, 1"/></geometry></visual>
  </link>
</robot>)";

TEST(LoadUrdf, CommaScaleKeepsGeometryAndJointsComposeAtZero) {
  testing::FixtureDataset fx;
  fx.write_text("urdf/box_cabinet/box_cabinet.urdf", kTwoLinkUrdf);
  const UrdfModel m = load_urdf(fx.root() / "urdf/box_cabinet/box_cabinet.urdf");
  ASSERT_EQ(m.links.size(), 3u);
  EXPECT_EQ(m.links[0].name, "root");
  EXPECT_EQ(m.links[1].name, "body");
  EXPECT_FALSE(m.links[1].movable);
  ASSERT_EQ(m.links[1].visuals.size(), 1u);  // urdfdom alone would drop it (comma scale)
  EXPECT_EQ(m.links[1].visuals[0].mesh.filename(), "body.obj");
  ASSERT_EQ(m.links[1].boxes.size(), 1u);
  EXPECT_NEAR(m.links[1].boxes[0].size.x(), 1.0, 1e-12);
  EXPECT_TRUE(m.links[2].movable);
  EXPECT_TRUE(m.links[2].X_RL.translation().isApprox(Eigen::Vector3d(0.5, 0.5, 0.25)));
}

TEST(LoadUrdf, UnparsableFileNamesTheFile) {
  testing::FixtureDataset fx;
  fx.write_text("urdf/bad/bad.urdf", "<robot name='x'><link name='a'><joint></robot>");
  try {
    load_urdf(fx.root() / "urdf/bad/bad.urdf");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.urdf: URDF does not parse"));
  }
}

TEST(LoadUrdf, ShippedKitchenCounterKeepsItsGeometry) {
  MTG_REQUIRE_SHIPPED_DATA();
  const UrdfModel m = load_urdf(testing::shipped_dataset()->urdfs.at("kitchen_counter"));
  EXPECT_EQ(m.links.size(), 9u);
  int with_visual = 0, boxes = 0, movable = 0;
  for (const auto& link : m.links) {
    with_visual += link.visuals.empty() ? 0 : 1;
    boxes += static_cast<int>(link.boxes.size());
    movable += link.movable ? 1 : 0;
  }
  EXPECT_EQ(with_visual, 8);  // body + 7 drawers
  EXPECT_EQ(movable, 7);      // the drawers hang on prismatic joints
  EXPECT_EQ(boxes, 12 + 7 * 5);
}

}  // namespace
}  // namespace mtg::scene
