#include "core/scene/scene_loader.h"

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "core/scene/urdf_model.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/parallel.h"
#include "core/util/stopwatch.h"

namespace mtg::scene {
namespace fs = std::filesystem;
namespace {

// Farther than this from the origin, a scene-file position is a mistake (the largest real scenes
// span tens of metres).
constexpr double kMaxCoordinate = 10000.0;

// Pose of a scene-file instance: Habitat is Y-up with quaternions [w, x, y, z].
struct HabitatPose {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

HabitatPose read_pose(const JsonField& instance) {
  HabitatPose pose;
  if (auto t = instance.find("translation")) {
    const auto v = t->as_doubles(3);
    pose.translation = Eigen::Vector3d(v[0], v[1], v[2]);
    // 1e308 m overflows every later step (meshes, grids, images) far from this file: say it here.
    if (!pose.translation.allFinite() || pose.translation.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      t->fail("a position more than " + std::to_string(static_cast<int>(kMaxCoordinate)) +
              " m from the origin (or not finite) is no place in a building");
    }
  }
  if (auto r = instance.find("rotation")) {
    const auto q = r->as_doubles(4);
    pose.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    if (pose.rotation.norm() < 1e-9) r->fail("zero quaternion");
    pose.rotation.normalize();
  }
  return pose;
}

// X_WO = C X_hab C^-1: the object frame O is the instance frame turned Z-up, so an upright
// object's pose is a yaw about +Z plus a translation.
Eigen::Isometry3d world_pose(const HabitatPose& pose) {
  const Eigen::Matrix3d C = yup_to_zup();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = C * pose.rotation.toRotationMatrix() * C.transpose();
  X.translation() = C * pose.translation;
  return X;
}

// Maps asset/link coordinates (Y-up, as authored) into O, applying the instance scale.
Eigen::Affine3d asset_to_object(const Eigen::Vector3d& scale,
                                const Eigen::Affine3d& inner = Eigen::Affine3d::Identity()) {
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.linear() = yup_to_zup();
  return T * Eigen::Scaling(scale) * inner;
}

MotionType parse_motion(const std::optional<JsonField>& field) {
  if (!field) return MotionType::kDynamic;
  const std::string s = field->as_string();
  if (s == "STATIC") return MotionType::kStatic;
  if (s == "KINEMATIC") return MotionType::kKinematic;
  if (s == "DYNAMIC" || s == "UNDEFINED") return MotionType::kDynamic;
  field->fail("unknown motion_type '" + s + "'");
}

Eigen::Vector3d instance_scale(const JsonField& instance) {
  Eigen::Vector3d s = Eigen::Vector3d::Ones();
  if (auto u = instance.find("uniform_scale")) s *= u->as_double();
  if (auto n = instance.find("non_uniform_scale")) {
    const auto v = n->as_doubles(3);
    s = s.cwiseProduct(Eigen::Vector3d(v[0], v[1], v[2]));
  }
  return s;
}

// receptacle_aabb_* entries of a user_defined block. `part_of_link` maps parent_link names to
// part indices (articulated objects); rigid objects attach everything to part 0.
std::vector<DeclaredReceptacle> read_receptacles(
    const JsonField& config, const std::map<std::string, int>& part_of_link,
    const std::vector<Eigen::Affine3d>& part_frames, std::vector<std::string>& warnings,
    const std::string& object_name) {
  std::vector<DeclaredReceptacle> out;
  const auto user = config.find("user_defined");
  if (!user || !user->is_object()) return out;
  for (const std::string& key : user->keys()) {
    if (key.rfind("receptacle_aabb", 0) != 0) continue;
    const JsonField r = user->at(key);
    DeclaredReceptacle rec;
    rec.name = key;
    if (auto link = r.find("parent_link")) {
      const auto it = part_of_link.find(link->as_string());
      if (it == part_of_link.end()) {
        warnings.push_back("receptacle " + key + " of " + object_name + ": unknown parent_link '" +
                           link->as_string() + "', skipped");
        continue;
      }
      rec.part = it->second;
    }
    const auto p = r.at("position").as_doubles(3);
    const auto s = r.at("scale").as_doubles(3);
    // Habitat builds the box with Range3D::fromCenter(position, scale): scale holds half extents
    // (some ao_configs write them negative).
    const Eigen::Vector3d centre(p[0], p[1], p[2]);
    const Eigen::Vector3d half = Eigen::Vector3d(s[0], s[1], s[2]).cwiseAbs();
    rec.box_R = Eigen::AlignedBox3d(centre - half, centre + half);
    if (auto up = r.find("up")) {
      const auto u = up->as_doubles(3);
      rec.up_R = Eigen::Vector3d(u[0], u[1], u[2]).normalized();
    }
    rec.T_OR = part_frames.at(static_cast<size_t>(rec.part));
    out.push_back(rec);
  }
  return out;
}

// Loads meshes once per file and turns failures into one warning per file.
class MeshLoader {
 public:
  /// `requested`, when given, receives every file asked for (loaded or not).
  MeshLoader(MeshCache& cache, Scene& scene, bool enabled, std::vector<fs::path>* requested = nullptr)
      : cache_(cache), scene_(scene), enabled_(enabled), requested_(requested) {}

  MeshHandle load(const fs::path& file, const std::string& object_name, const char* fallback) {
    if (requested_ != nullptr && !file.empty()) requested_->push_back(file);
    if (!enabled_ || file.empty()) return nullptr;
    const std::string key = file.lexically_normal().string();
    if (failed_.count(key) != 0) return nullptr;
    try {
      MeshHandle mesh = cache_.get(file);
      used_.insert(key);
      return mesh;
    } catch (const Error& e) {
      failed_.insert(key);
      scene_.warnings.push_back(std::string(fs::exists(file) ? "broken mesh" : "mesh missing") +
                                " for " + object_name + ": " + e.what() + "; " + fallback);
      return nullptr;
    }
  }
  bool enabled() const { return enabled_; }
  int loaded() const { return static_cast<int>(used_.size()); }
  int missing() const { return static_cast<int>(failed_.size()); }

 private:
  MeshCache& cache_;
  Scene& scene_;
  bool enabled_;
  std::vector<fs::path>* requested_;
  std::set<std::string> used_;
  std::set<std::string> failed_;
};

std::string make_unique_name(std::string name, std::set<std::string>& taken) {
  std::string candidate = name;
  for (int k = 2; taken.count(candidate) != 0; ++k) candidate = name + "_v" + std::to_string(k);
  taken.insert(candidate);
  return candidate;
}

void load_rigid_objects(const Dataset& ds, const JsonField& list, MeshLoader& meshes,
                        std::set<std::string>& taken, Scene& scene) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonField inst = list.at(i);
    const std::string tmpl = template_basename(inst.at("template_name").as_string());
    ObjectInstance obj;
    obj.template_name = tmpl;
    obj.short_name = ds.short_name(tmpl);
    obj.file_index = static_cast<int>(i);
    obj.name = make_unique_name(obj.short_name + "_" + std::to_string(i), taken);
    obj.motion = parse_motion(inst.find("motion_type"));
    obj.scale = instance_scale(inst);

    const auto cfg_it = ds.object_configs.find(tmpl);
    if (cfg_it == ds.object_configs.end()) {
      scene.warnings.push_back(inst.where() + ": object " + obj.name + ": no object config for template '" + tmpl +
                               "' in the dataset, skipped");
      continue;
    }
    const fs::path cfg_file = cfg_it->second;
    scene.source_files.insert(cfg_file);
    const nlohmann::json cfg_json = read_json_file(cfg_file);
    const JsonField cfg(cfg_json, cfg_file.string());
    if (auto s = cfg.find("scale")) {
      const auto v = s->as_doubles(3);
      obj.scale = obj.scale.cwiseProduct(Eigen::Vector3d(v[0], v[1], v[2]));
    }
    if (auto sid = cfg.find("semantic_id")) {
      const auto it = ds.semantic_classes.find(static_cast<int>(sid->as_double()));
      if (it != ds.semantic_classes.end()) obj.category = it->second;
    }

    HabitatPose pose = read_pose(inst);
    // translation_origin COM: the file gives the centre of mass, not the asset origin.
    if (auto origin = inst.find("translation_origin"); origin && origin->as_string() == "COM") {
      if (auto com = cfg.find("COM")) {
        const auto c = com->as_doubles(3);
        pose.translation -= pose.rotation * obj.scale.cwiseProduct(Eigen::Vector3d(c[0], c[1], c[2]));
      }
    }
    obj.X_WO = world_pose(pose);

    Part part;
    part.T_OA = asset_to_object(obj.scale);
    part.T_OC = part.T_OA;
    part.render_path = (cfg_file.parent_path() / cfg.at("render_asset").as_string()).lexically_normal();
    // Collision geometry: the dataset's collision_asset (a convex decomposition), else the
    // <render>.convex.stl hull beside the render asset, else the render mesh itself.
    std::vector<fs::path> collision_candidates;
    if (auto c = cfg.find("collision_asset")) {
      collision_candidates.push_back((cfg_file.parent_path() / c->as_string()).lexically_normal());
    }
    collision_candidates.push_back(fs::path(part.render_path.string() + ".convex.stl"));
    scene.source_files.insert(part.render_path);
    for (const auto& c : collision_candidates) {
      if (fs::exists(c)) {
        scene.source_files.insert(c);
        part.collision_path = c;
        break;
      }
    }
    part.render = meshes.load(part.render_path, obj.name,
                              "using its collision mesh for geometry");
    if (!part.collision_path.empty()) {
      part.collision = meshes.load(part.collision_path, obj.name, "using the render mesh");
    }
    if (!part.collision) {
      part.collision = part.render;
      part.collision_path = part.render ? part.render_path : fs::path();
    }
    if (!part.render && !part.collision && meshes.enabled()) {
      scene.warnings.push_back("object " + obj.name + ": no geometry at all (render and collision "
                               "meshes unavailable)");
    }
    obj.parts.push_back(part);
    obj.receptacles = read_receptacles(cfg, {}, {part.T_OA}, scene.warnings, obj.name);
    scene.objects.push_back(std::move(obj));
  }
}

void load_articulated_objects(const Dataset& ds, const JsonField& list, MeshLoader& meshes,
                              std::set<std::string>& taken, Scene& scene) {
  const int offset = static_cast<int>(scene.objects.size());
  for (std::size_t j = 0; j < list.size(); ++j) {
    const JsonField inst = list.at(j);
    const std::string tmpl = template_basename(inst.at("template_name").as_string());
    ObjectInstance obj;
    obj.articulated = true;
    obj.template_name = tmpl;
    obj.short_name = ds.short_name(tmpl);
    obj.file_index = offset + static_cast<int>(j);
    obj.name = make_unique_name(obj.short_name + "_" + std::to_string(j), taken);
    obj.motion = parse_motion(inst.find("motion_type"));
    obj.scale = instance_scale(inst);
    obj.X_WO = world_pose(read_pose(inst));

    const auto urdf_it = ds.urdfs.find(tmpl);
    if (urdf_it == ds.urdfs.end()) {
      scene.warnings.push_back(inst.where() + ": articulated object " + obj.name + ": no URDF for template '" +
                               tmpl + "' in the dataset, skipped");
      continue;
    }
    UrdfModel model;
    scene.source_files.insert(urdf_it->second);
    try {
      model = load_urdf(urdf_it->second);
    } catch (const Error& e) {
      scene.warnings.push_back("articulated object " + obj.name + ": " + e.what() + ", skipped");
      continue;
    }

    std::map<std::string, int> part_of_link;
    std::vector<Eigen::Affine3d> link_frames;
    for (const UrdfLink& link : model.links) {
      const Eigen::Affine3d T_OL = asset_to_object(obj.scale, Eigen::Affine3d(link.X_RL.matrix()));
      part_of_link[link.name] = static_cast<int>(obj.parts.size());
      link_frames.push_back(T_OL);
      Part part;
      part.link = link.name;
      part.movable_link = link.movable;
      part.T_OA = T_OL;
      if (!link.visuals.empty()) {
        const UrdfVisual& v = link.visuals.front();
        part.T_OA = T_OL * Eigen::Affine3d(v.X_LV.matrix()) * Eigen::Scaling(v.scale);
        part.render_path = v.mesh;
        scene.source_files.insert(v.mesh);
        part.render = meshes.load(v.mesh, obj.name + "/" + link.name,
                                  "using its URDF collision boxes for geometry");
      }
      part.T_OC = part.T_OA;
      part.collision = part.render;
      part.collision_path = part.render_path;
      for (const UrdfBox& b : link.boxes) {
        const Eigen::Affine3d T_OB = T_OL * Eigen::Affine3d(b.X_LB.matrix());
        CollisionBox box;
        box.X_OB.translation() = T_OB.translation();
        box.X_OB.linear() = yup_to_zup() * (link.X_RL * b.X_LB).rotation();
        box.size = b.size.cwiseProduct(obj.scale.cwiseAbs());
        part.collision_boxes.push_back(box);
      }
      obj.parts.push_back(std::move(part));
    }

    const fs::path ao_config =
        urdf_it->second.parent_path() / (urdf_it->second.stem().string() + ".ao_config.json");
    if (fs::exists(ao_config)) {
      scene.source_files.insert(ao_config);
      const nlohmann::json ao_json = read_json_file(ao_config);
      obj.receptacles = read_receptacles(JsonField(ao_json, ao_config.string()), part_of_link,
                                         link_frames, scene.warnings, obj.name);
    }
    scene.objects.push_back(std::move(obj));
  }
}

// One pass over the scene's files; with `requested`, the mesh files it asks for are noted too.
Scene load_once(const Dataset& ds, const std::string& scene_name, MeshCache& cache, bool load_meshes,
                std::vector<fs::path>* requested) {
  Scene scene;
  scene.name = scene_name;
  scene.data_root = ds.root;
  scene.scene_file = ds.scene_file(scene_name);
  scene.source_files.insert(scene.scene_file);

  const nlohmann::json doc = read_json_file(scene.scene_file);
  const JsonField root(doc, scene.scene_file.string());
  if (!root.is_object()) root.fail("expected a scene instance object");

  if (auto stage = root.find("stage_instance")) {
    scene.stage_template = template_basename(stage->at("template_name").as_string());
    if (const auto it = ds.stage_configs.find(scene.stage_template); it != ds.stage_configs.end()) {
      scene.source_files.insert(it->second);
      const nlohmann::json stage_json = read_json_file(it->second);
      const JsonField stage_cfg(stage_json, it->second.string());
      if (auto asset = stage_cfg.find("render_asset")) {
        scene.stage_mesh_present = fs::exists(it->second.parent_path() / asset->as_string());
      }
    }
  }

  MeshLoader meshes(cache, scene, load_meshes, requested);
  std::set<std::string> taken;
  if (auto list = root.find("object_instances")) {
    load_rigid_objects(ds, *list, meshes, taken, scene);
  }
  if (auto list = root.find("articulated_object_instances")) {
    load_articulated_objects(ds, *list, meshes, taken, scene);
  }
  scene.stats.meshes_loaded = meshes.loaded();
  scene.stats.meshes_missing = meshes.missing();
  return scene;
}

}  // namespace

Scene load_scene(const Dataset& ds, const std::string& scene_name, MeshCache& cache,
                 const SceneLoadOptions& options) {
  const Stopwatch watch;
  if (options.load_meshes && options.jobs > 1) {
    // Reading meshes is most of the time: the file names first (the configs alone, which is
    // quick), then the files on every thread into the cache. The scene is then put together as
    // on one thread, from the cache; a file that fails is read again there and warned about.
    std::vector<fs::path> files;
    load_once(ds, scene_name, cache, /*load_meshes=*/false, &files);
    std::sort(files.begin(), files.end());
    files.erase(std::unique(files.begin(), files.end()), files.end());
    parallel_for(files.size(), options.jobs, [&](std::size_t i) {
      try {
        cache.get(files[i]);
      } catch (const Error&) {  // missing or broken: the pass below says so, once
      }
    });
  }
  Scene scene = load_once(ds, scene_name, cache, options.load_meshes, nullptr);
  scene.stats.load_ms = watch.elapsed_ms();
  return scene;
}

std::vector<std::filesystem::path> files_to_copy(const Dataset& dataset, const Scene& scene) {
  std::set<std::filesystem::path> files(scene.source_files);
  files.insert(dataset.config_files.begin(), dataset.config_files.end());
  std::vector<std::filesystem::path> out;
  // Files looked for in vain (an absent mesh) stay out: a copy has them absent too.
  for (const std::filesystem::path& f : files) {
    if (std::filesystem::is_regular_file(f)) out.push_back(f);
  }
  return out;
}

}  // namespace mtg::scene
