#include "core/scene/dataset.h"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/scene/dataset_fingerprint.h"
#include "core/util/error.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/shipped_data.h"
#include "tests/support/text_file.h"

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


// The hashes of unchanged files come from the cache, and nothing else does: a file rewritten to
// the same size with its old modification time is read again (its change time moved), a damaged
// or linked cache is left alone and every hash is still right.
TEST(FileHashCache, RemembersOnlyTheVersionItReadAndNeverGivesAWrongHash) {
  namespace fs = std::filesystem;
  testing::FixtureDataset fx;
  std::set<fs::path> files;
  for (int i = 0; i < 4; ++i) {
    fx.add_raw_file("part_" + std::to_string(i) + ".bin", std::string(5000, static_cast<char>('a' + i)));
    files.insert(fx.root() / ("objects/part_" + std::to_string(i) + ".bin"));
  }
  const fs::path cache_file = fx.root() / "cache" / "file-hashes.sqlite";
  fs::create_directories(cache_file.parent_path());
  const auto with_cache = [&] { return std::make_unique<FileHashCache>(cache_file, std::chrono::nanoseconds(0)); };
  const auto read_all = [&] {
    FileHashes none(nullptr);
    return fingerprint_files(fx.root(), files, &none);
  };
  const DatasetFingerprint truth = read_all();
  {
    FileHashes first(with_cache());
    EXPECT_EQ(fingerprint_files(fx.root(), files, &first).files, truth.files);
    EXPECT_EQ(first.cached(), 0);
  }
  {
    FileHashes second(with_cache());
    EXPECT_EQ(fingerprint_files(fx.root(), files, &second).files, truth.files);
    EXPECT_EQ(second.cached(), 4) << "every unchanged file from the cache";
  }
  // Same size, other bytes, the old modification time put back.
  const fs::path part0 = fx.root() / "objects/part_0.bin";
  const auto old_time = fs::last_write_time(part0);
  std::ofstream(part0, std::ios::binary | std::ios::trunc) << std::string(5000, 'z');
  fs::last_write_time(part0, old_time);
  const DatasetFingerprint changed = read_all();
  ASSERT_NE(changed.files.at("objects/part_0.bin"), truth.files.at("objects/part_0.bin"));
  {
    FileHashes third(with_cache());
    EXPECT_EQ(fingerprint_files(fx.root(), files, &third).files, changed.files);
    EXPECT_EQ(third.cached(), 3) << "the rewritten file was read again";
  }
  // A file changed just now is not remembered: two writes within one clock tick show one time.
  {
    FileHashCache settling(cache_file, std::chrono::hours(1));
    const auto stamp = FileStamp::of(part0);
    ASSERT_TRUE(stamp.has_value());
    settling.remember(fs::absolute(part0), *stamp, "0123456789abcdef");
    EXPECT_EQ(settling.find(fs::absolute(part0), *stamp), changed.files.at("objects/part_0.bin"));
  }
  // Damaged: refused, nothing read from it, every hash still right.
  fs::remove(cache_file.string() + "-wal");
  fs::remove(cache_file.string() + "-shm");
  std::ofstream(cache_file, std::ios::binary | std::ios::trunc) << "not a database at all, just some bytes here";
  EXPECT_THROW(FileHashCache{cache_file}, Error);
  // A link planted at its name: not followed, its target untouched.
  const fs::path target = fx.root() / "precious.txt";
  std::ofstream(target) << "keep me";
  fs::remove(cache_file);
  fs::create_symlink(target, cache_file);
  EXPECT_THROW(FileHashCache{cache_file}, Error);
  EXPECT_EQ(testing::read_text(target), "keep me");
  ::setenv("MTG_CACHE_DIR", cache_file.parent_path().c_str(), 1);
  {
    FileHashes through_env;  // the planted link turns the cache off; the hashes are read
    EXPECT_EQ(fingerprint_files(fx.root(), files, &through_env).files, changed.files);
    EXPECT_EQ(through_env.cached(), 0);
  }
  ::setenv("MTG_CACHE_DIR", "off", 1);
  EXPECT_EQ(FileHashCache::open_default(), nullptr);
  ::unsetenv("MTG_CACHE_DIR");
}

}  // namespace
}  // namespace mtg::scene
