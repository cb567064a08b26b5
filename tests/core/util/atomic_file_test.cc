#include "core/util/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/util/error.h"

namespace mtg {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mtg_atomic_file_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static void write_hello(std::ostream& out) { out << "hello"; }
  fs::path dir_;
};

TEST_F(AtomicFile, ReplacesARegularFileOrWritesANewOne) {
  const fs::path f = dir_ / "out.txt";
  write_file_atomically(f, write_hello);
  write_file_atomically(f, write_hello);
  std::ifstream in(f);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // no partial left
}

// `--out /dev/null` as root replaced the device with a file. A FIFO, a folder and a link to a
// FIFO stand in for it here: the same test refuses them all, before anything is written.
TEST_F(AtomicFile, NeverRenamesOverWhatIsNotARegularFile) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path folder = dir_ / "folder";
  fs::create_directories(folder);
  const fs::path link = dir_ / "link";
  fs::create_symlink(fifo, link);
  for (const fs::path& target : {fifo, folder, link}) {
    try {
      write_file_atomically(target, write_hello);
      ADD_FAILURE() << target << " was written over";
    } catch (const Error& e) {
      EXPECT_THAT(e.what(), HasSubstr(target.string())) << "the error names the path";
      EXPECT_THAT(std::string(e.what()), ::testing::AnyOf(HasSubstr("FIFO"), HasSubstr("folder")));
    }
  }
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_TRUE(fs::is_directory(folder));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 3);  // no partial left
}

TEST_F(AtomicFile, ChecksAgainWhenItCommits) {
  const fs::path target = dir_ / "late";
  PartialFile partial(target);
  ASSERT_EQ(::mkfifo(target.c_str(), 0600), 0);  // made while the writer was writing
  EXPECT_THROW(partial.commit(), Error);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(target)));
}

}  // namespace
}  // namespace mtg
