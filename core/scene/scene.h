#pragma once
// The typed scene: every object instance of a ReplicaCAD-format scene with its pose in the
// Z-up world, its meshes and its declared receptacles. Built by load_scene() (scene_loader.h).
//
// Frames (see docs/scene.md):
//   W  world, Z-up, metres; floor is z = 0.
//   O  object frame: the instance's pose converted to Z-up (X_WO is a rigid transform).
//   A  asset frame of one part's mesh file (Y-up as authored, node transforms applied).
//   T_OA maps asset coordinates into O and carries the instance's scale.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "core/scene/mesh.h"

namespace mtg::scene {

enum class MotionType { kStatic, kDynamic, kKinematic };
const char* to_string(MotionType type);

/// A box of an articulated link's collision geometry (URDF <box>), in the object frame.
struct CollisionBox {
  Eigen::Isometry3d X_OB = Eigen::Isometry3d::Identity();  // box centre pose in O
  Eigen::Vector3d size = Eigen::Vector3d::Zero();          // full edge lengths, metres
};

/// One rigid piece of an instance: the whole object for rigid objects, a link for articulated ones.
struct Part {
  std::string link;            // URDF link name ("" for rigid objects)
  bool movable_link = false;   // reached through a non-fixed joint (door, drawer)
  Eigen::Affine3d T_OA = Eigen::Affine3d::Identity();  // asset coordinates -> O (with scale)
  std::filesystem::path render_path;
  MeshHandle render;           // null when the file is missing or broken (see warnings)
  std::filesystem::path collision_path;
  MeshHandle collision;        // collision mesh; null when none could be loaded
  Eigen::Affine3d T_OC = Eigen::Affine3d::Identity();  // collision asset coordinates -> O
  std::vector<CollisionBox> collision_boxes;           // URDF boxes (articulated links)
};

/// A receptacle the dataset declares (user_defined.receptacle_aabb_* in an object or ao config).
struct DeclaredReceptacle {
  std::string name;          // the dataset key
  int part = 0;              // index into ObjectInstance::parts it is attached to
  Eigen::AlignedBox3d box_R; // axis-aligned box in its own frame R (half extents already applied)
  Eigen::Affine3d T_OR = Eigen::Affine3d::Identity();  // R -> O (the part's frame, with scale)
  Eigen::Vector3d up_R{0.0, 1.0, 0.0};                 // "up" in R (dataset default +Y)
};

struct ObjectInstance {
  std::string name;           // unique, stable: "<short template>_<index in file order>"
  std::string template_name;  // dataset template, e.g. "frl_apartment_table_02"
  std::string short_name;     // template without the dataset's common prefix, e.g. "table_02"
  std::string category;       // semantic class from the dataset lexicon ("" if none)
  int file_index = 0;         // position in the scene file's list (objects, then articulated)
  bool articulated = false;
  MotionType motion = MotionType::kDynamic;
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  std::vector<Part> parts;
  std::vector<DeclaredReceptacle> receptacles;

  /// World-frame AABB of all part render meshes (collision geometry when render is missing).
  Eigen::AlignedBox3d world_bounds() const;
  std::size_t render_triangles() const;
};

struct LoadStats {
  double load_ms = 0.0;          // telemetry
  int meshes_loaded = 0;         // distinct mesh files read
  int meshes_missing = 0;        // referenced files that are absent or unreadable
};

struct Scene {
  std::string name;
  std::filesystem::path data_root;
  std::filesystem::path scene_file;
  std::string stage_template;
  bool stage_mesh_present = false;
  std::vector<ObjectInstance> objects;  // rigid objects in file order, then articulated
  std::vector<std::string> warnings;    // one line each, naming the object and file
  LoadStats stats;
  /// Every file the scene was made from, present or looked for in vain: the scene instance, stage
  /// and object configs, URDFs, meshes (dataset_fingerprint.h ties a task set to them).
  std::set<std::filesystem::path> source_files;

  const ObjectInstance* find(const std::string& name) const;
};

/// Y-up (x, y, z) -> Z-up (x, -z, y): the rotation Rx(+90 deg).
Eigen::Matrix3d yup_to_zup();

}  // namespace mtg::scene
