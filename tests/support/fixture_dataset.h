#pragma once
// Small ReplicaCAD-format datasets that tests build themselves in a temporary directory:
// OBJ box meshes (Y-up, metres, as the dataset's assets), object configs and scene instances.

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mtg::testing {

class FixtureDataset {
 public:
  FixtureDataset();
  ~FixtureDataset();
  FixtureDataset(const FixtureDataset&) = delete;
  FixtureDataset& operator=(const FixtureDataset&) = delete;

  const std::filesystem::path& root() const { return root_; }

  /// Writes objects/<name>.obj: an axis-aligned box of `size` (x, y-up, z) whose bottom face
  /// centre is at `bottom_centre` (asset frame). Returns the path relative to configs/objects.
  std::string add_box_mesh(const std::string& name, const Eigen::Vector3d& size,
                           const Eigen::Vector3d& bottom_centre = Eigen::Vector3d::Zero());
  /// Several boxes in one OBJ file (e.g. a table top on legs, a shelf with layers).
  struct Box {
    Eigen::Vector3d size;
    Eigen::Vector3d bottom_centre;
    Eigen::Vector3d rgb = -Eigen::Vector3d::Ones();  // diffuse colour 0..1 (an .mtl); negative: none
  };
  std::string add_boxes_mesh(const std::string& name, const std::vector<Box>& boxes);
  /// Writes raw bytes as objects/<file>.
  std::string add_raw_file(const std::string& file, const std::string& bytes);

  /// configs/objects/<template>.object_config.json with render_asset = `mesh` plus `extra` keys.
  void add_object_config(const std::string& template_name, const std::string& mesh,
                         const nlohmann::json& extra = nlohmann::json::object());
  /// configs/scenes/<name>.scene_instance.json.
  void add_scene(const std::string& name, const nlohmann::json& scene);
  /// Writes an arbitrary text file at `relative` (e.g. a URDF).
  void write_text(const std::string& relative, const std::string& text);

  /// A scene-instance entry in Habitat convention: Y-up translation, [w, x, y, z] rotation.
  static nlohmann::json instance(const std::string& template_name, const Eigen::Vector3d& t_yup,
                                 double yaw_deg = 0.0, const std::string& motion = "DYNAMIC");

 private:
  std::filesystem::path root_;
};

}  // namespace mtg::testing
