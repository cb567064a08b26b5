#pragma once
// Articulated objects from their URDF (urdfdom), at the closed configuration (all joints 0).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

namespace mtg::scene {

struct UrdfVisual {
  Eigen::Isometry3d X_LV = Eigen::Isometry3d::Identity();  // visual origin in the link frame
  std::filesystem::path mesh;                              // absolute path of the mesh file
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

struct UrdfBox {
  Eigen::Isometry3d X_LB = Eigen::Isometry3d::Identity();  // box centre in the link frame
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
};

struct UrdfLink {
  std::string name;
  bool movable = false;  // some joint between the root and this link is not fixed
  Eigen::Isometry3d X_RL = Eigen::Isometry3d::Identity();  // link pose in the root frame, q = 0
  std::vector<UrdfVisual> visuals;
  std::vector<UrdfBox> boxes;
};

struct UrdfModel {
  std::vector<UrdfLink> links;  // depth-first from the root, children in file order
};

/// urdfdom rejects comma-separated vectors such as scale="1, 1, 1" (and one shipped box
/// size="0.617 0.145, 0.894") and then silently drops that geometry; rewrite the commas inside
/// scale, size, xyz, rpy and axis attributes as spaces before parsing.
std::string normalize_urdf_vector_attributes(std::string xml);

/// Parses a URDF file. @throws mtg::Error naming the file if it is missing or does not parse.
UrdfModel load_urdf(const std::filesystem::path& file);

}  // namespace mtg::scene
