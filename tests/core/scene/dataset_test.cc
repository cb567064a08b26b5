#include "core/scene/dataset.h"

#include <set>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/scene/dataset_fingerprint.h"
#include "core/util/error.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/shipped_data.h"

namespace mtg::scene {
namespace {

using ::testing::HasSubstr;

TEST(ResolveDataRoot, ExplicitDirectoryThatDoesNotExistIsAnError) {
  try {
    resolve_data_root("/nonexistent/mtg/data");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("data directory does not exist: /nonexistent/mtg/data"));
  }
}

TEST(IndexDataset, DirectoryWithoutScenesIsAnError) {
  testing::FixtureDataset fx;
  EXPECT_THROW(index_dataset(fx.root()), Error);
}

TEST(IndexDataset, UnknownSceneListsTheAvailableOnes) {
  testing::FixtureDataset fx;
  fx.add_scene("alpha", {{"object_instances", nlohmann::json::array()}});
  fx.add_scene("beta", {{"object_instances", nlohmann::json::array()}});
  const Dataset ds = index_dataset(fx.root());
  try {
    ds.scene_file("gamma");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown scene 'gamma'"));
    EXPECT_THAT(e.what(), HasSubstr("available: alpha, beta"));
  }
}

TEST(IndexDataset, ShortNamesDropTheCommonTemplatePrefix) {
  testing::FixtureDataset fx;
  const auto mesh = fx.add_box_mesh("box", {0.1, 0.1, 0.1});
  fx.add_object_config("acme_home_box_01", mesh);
  fx.add_object_config("acme_home_table", mesh);
  fx.add_scene("s", {{"object_instances", nlohmann::json::array()}});
  const Dataset ds = index_dataset(fx.root());
  EXPECT_EQ(ds.object_prefix, "acme_home_");
  EXPECT_EQ(ds.short_name("acme_home_box_01"), "box_01");
  EXPECT_EQ(ds.short_name("other"), "other");
}

TEST(IndexDataset, ShippedDatasetHasTheApartments) {
  MTG_REQUIRE_SHIPPED_DATA();
  const Dataset& ds = *testing::shipped_dataset();
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    EXPECT_TRUE(ds.scenes.count(name)) << name;
  }
  EXPECT_EQ(ds.object_prefix, "frl_apartment_");
  EXPECT_TRUE(ds.urdfs.count("fridge"));
  EXPECT_TRUE(ds.urdfs.count("chestOfDrawers_01"));  // stored under urdf/chest_of_drawers/
  EXPECT_EQ(ds.semantic_classes.at(13), "book");
}

// Several scenes' fingerprints read shared files once through one FileHashes, from several
// threads at once: the same fingerprints as reading every file for every scene.
TEST(DatasetFingerprint, SharedFileHashesGiveTheSameFingerprintsFromAnyThread) {
  testing::FixtureDataset fx;
  std::set<std::filesystem::path> files;
  for (int i = 0; i < 12; ++i) {
    fx.add_raw_file("part_" + std::to_string(i) + ".bin", std::string(1000 + 37 * i, static_cast<char>('a' + i)));
    files.insert(fx.root() / ("objects/part_" + std::to_string(i) + ".bin"));
  }
  files.insert(fx.root() / "objects/absent.glb");
  const DatasetFingerprint alone = fingerprint_files(fx.root(), files);
  EXPECT_EQ(alone.files.at("objects/absent.glb"), kMissingFile);
  EXPECT_NE(alone.files.at("objects/part_0.bin"), alone.files.at("objects/part_1.bin"));
  FileHashes hashes;
  std::vector<DatasetFingerprint> shared(8);
  std::vector<std::thread> threads;
  for (auto& f : shared) threads.emplace_back([&] { f = fingerprint_files(fx.root(), files, &hashes); });
  for (auto& t : threads) t.join();
  for (const auto& f : shared) EXPECT_EQ(f.files, alone.files);
  EXPECT_EQ(first_difference(alone, fx.root(), &hashes), "");
}

}  // namespace
}  // namespace mtg::scene
