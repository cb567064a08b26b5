#include "core/scene/urdf_model.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <sstream>

#include "core/util/error.h"

namespace mtg::scene {
namespace {

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  X.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y,
                                  pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return X;
}

void visit(const urdf::ModelInterface& model, const urdf::LinkConstSharedPtr& link,
           const Eigen::Isometry3d& X_RL, bool movable, const std::filesystem::path& dir,
           UrdfModel& out) {
  UrdfLink entry;
  entry.name = link->name;
  entry.movable = movable;
  entry.X_RL = X_RL;
  for (const auto& visual : link->visual_array) {
    if (!visual || !visual->geometry || visual->geometry->type != urdf::Geometry::MESH) continue;
    const auto mesh = std::dynamic_pointer_cast<urdf::Mesh>(visual->geometry);
    UrdfVisual v;
    v.X_LV = to_isometry(visual->origin);
    v.mesh = (dir / mesh->filename).lexically_normal();
    v.scale = Eigen::Vector3d(mesh->scale.x, mesh->scale.y, mesh->scale.z);
    entry.visuals.push_back(v);
  }
  for (const auto& collision : link->collision_array) {
    if (!collision || !collision->geometry || collision->geometry->type != urdf::Geometry::BOX) {
      continue;
    }
    const auto box = std::dynamic_pointer_cast<urdf::Box>(collision->geometry);
    UrdfBox b;
    b.X_LB = to_isometry(collision->origin);
    b.size = Eigen::Vector3d(box->dim.x, box->dim.y, box->dim.z);
    entry.boxes.push_back(b);
  }
  out.links.push_back(std::move(entry));

  for (const auto& joint : link->child_joints) {
    const auto child = model.getLink(joint->child_link_name);
    if (!child) continue;
    // Closed configuration: every joint at 0, so only the joint origin contributes.
    const Eigen::Isometry3d X_RC = X_RL * to_isometry(joint->parent_to_joint_origin_transform);
    visit(model, child, X_RC, movable || joint->type != urdf::Joint::FIXED, dir, out);
  }
}

}  // namespace

std::string normalize_urdf_vector_attributes(std::string xml) {
  for (const std::string key : {" scale=\"", " size=\"", " xyz=\"", " rpy=\"", " axis=\""}) {
    std::size_t pos = 0;
    while ((pos = xml.find(key, pos)) != std::string::npos) {
      const std::size_t start = pos + key.size();
      const std::size_t end = xml.find('"', start);
      if (end == std::string::npos) break;
      for (std::size_t i = start; i < end; ++i) {
        if (xml[i] == ',') xml[i] = ' ';
      }
      pos = end + 1;
    }
  }
  return xml;
}

UrdfModel load_urdf(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open URDF");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const auto model = urdf::parseURDF(normalize_urdf_vector_attributes(buffer.str()));
  if (!model || !model->getRoot()) throw Error(file.string() + ": URDF does not parse");
  UrdfModel out;
  visit(*model, model->getRoot(), Eigen::Isometry3d::Identity(), false, file.parent_path(), out);
  return out;
}

}  // namespace mtg::scene
