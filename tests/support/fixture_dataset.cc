#include "tests/support/fixture_dataset.h"


#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>

namespace mtg::testing {
namespace fs = std::filesystem;

FixtureDataset::FixtureDataset() {
  // Unique per test: the test name plus the process id.
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string stem = info ? std::string(info->test_suite_name()) + "." + info->name() : "fixture";
  root_ = fs::path(::testing::TempDir()) / ("mtg_" + stem + "_" + std::to_string(::getpid()));
  fs::remove_all(root_);
  fs::create_directories(root_ / "configs/objects");
  fs::create_directories(root_ / "configs/scenes");
  fs::create_directories(root_ / "objects");
}

FixtureDataset::~FixtureDataset() {
  if (std::getenv("MTG_KEEP_FIXTURES") != nullptr) return;  // to look at a failed test's files
  std::error_code ec;
  fs::remove_all(root_, ec);
}

std::string FixtureDataset::add_box_mesh(const std::string& name, const Eigen::Vector3d& size,
                                         const Eigen::Vector3d& bottom_centre) {
  return add_boxes_mesh(name, {Box{size, bottom_centre}});
}

std::string FixtureDataset::add_boxes_mesh(const std::string& name, const std::vector<Box>& boxes) {
  std::ofstream out(root_ / "objects" / (name + ".obj"));
  const bool coloured = std::any_of(boxes.begin(), boxes.end(), [](const Box& b) { return b.rgb.x() >= 0; });
  if (coloured) {
    std::ofstream mtl(root_ / "objects" / (name + ".mtl"));
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const Eigen::Vector3d c = boxes[k].rgb.cwiseMax(0.0);
      mtl << "newmtl m" << k << "\nKd " << c.x() << ' ' << c.y() << ' ' << c.z() << "\n";
    }
    out << "mtllib " << name << ".mtl\n";
  }
  int base = 1;
  int k = 0;
  for (const Box& b : boxes) {
    if (coloured) out << "usemtl m" << k++ << '\n';
    const Eigen::Vector3d lo = b.bottom_centre - Eigen::Vector3d(b.size.x() / 2, 0, b.size.z() / 2);
    const Eigen::Vector3d hi = lo + b.size;
    for (int i = 0; i < 8; ++i) {
      out << "v " << ((i & 1) ? hi.x() : lo.x()) << ' ' << ((i & 2) ? hi.y() : lo.y()) << ' '
          << ((i & 4) ? hi.z() : lo.z()) << '\n';
    }
    // Outward-facing quads (counter-clockwise seen from outside), split into triangles.
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
      out << "f " << base + q[0] << ' ' << base + q[1] << ' ' << base + q[2] << '\n';
      out << "f " << base + q[0] << ' ' << base + q[2] << ' ' << base + q[3] << '\n';
    }
    base += 8;
  }
  return "../../objects/" + name + ".obj";
}

std::string FixtureDataset::add_raw_file(const std::string& file, const std::string& bytes) {
  std::ofstream out(root_ / "objects" / file, std::ios::binary);
  out << bytes;
  return "../../objects/" + file;
}

void FixtureDataset::add_object_config(const std::string& template_name, const std::string& mesh,
                                       const nlohmann::json& extra) {
  nlohmann::json cfg = extra;
  cfg["render_asset"] = mesh;
  std::ofstream(root_ / "configs/objects" / (template_name + ".object_config.json")) << cfg.dump(2);
}

void FixtureDataset::add_scene(const std::string& name, const nlohmann::json& scene) {
  std::ofstream(root_ / "configs/scenes" / (name + ".scene_instance.json")) << scene.dump(2);
}

void FixtureDataset::write_text(const std::string& relative, const std::string& text) {
  fs::create_directories((root_ / relative).parent_path());
  std::ofstream(root_ / relative) << text;
}

nlohmann::json FixtureDataset::instance(const std::string& template_name,
                                        const Eigen::Vector3d& t_yup, double yaw_deg,
                                        const std::string& motion) {
  const double half = yaw_deg * M_PI / 360.0;
  return {{"template_name", "objects/" + template_name},
          {"motion_type", motion},
          {"translation", {t_yup.x(), t_yup.y(), t_yup.z()}},
          {"rotation", {std::cos(half), 0.0, std::sin(half), 0.0}}};
}

}  // namespace mtg::testing
