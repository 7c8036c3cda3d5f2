// SPDX-License-Identifier: MIT
// host/output/whole_folder.hpp: an output folder is checked before any work and replaced
// whole or not at all; a run that does not commit leaves the previous folder and nothing
// else behind.

#include "host/output/whole_folder.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using excite::host::WholeFolder;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class WholeFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_whole_folder_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Entries of the test folder other than `out` (a temporary folder left behind).
  std::string others() const {
    std::string names;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename() != "out") names += e.path().filename().string() + " ";
    return names;
  }
  fs::path dir_;
};

TEST_F(WholeFolderTest, NewFolderAppearsOnlyAtCommit) {
  WholeFolder folder(dir_ / "out", false, "test");
  std::ofstream(folder.staging() / "a.txt") << "new\n";
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  folder.commit();
  EXPECT_EQ(read(dir_ / "out/a.txt"), "new\n");
  EXPECT_EQ(others(), "");
}

// The output of an earlier run of the same kind (its marker lists everything in it).
void write_previous(const fs::path& out) {
  WholeFolder folder(out, false, "test");
  std::ofstream(folder.staging() / "marker") << "old\n";
  fs::create_directories(folder.staging() / "sub");
  std::ofstream(folder.staging() / "sub/old.txt") << "old\n";
  folder.commit();
}

TEST_F(WholeFolderTest, PreviousOutputIsReplacedWhole) {
  write_previous(dir_ / "out");
  EXPECT_EQ(read(dir_ / "out/.excite-output"),
            "excite output v1 test\nmarker\nsub/\nsub/old.txt\n");
  WholeFolder folder(dir_ / "out", false, "test");
  std::ofstream(folder.staging() / "marker") << "new\n";
  EXPECT_EQ(read(dir_ / "out/marker"), "old\n");
  folder.commit();
  EXPECT_EQ(read(dir_ / "out/marker"), "new\n");
  EXPECT_FALSE(fs::exists(dir_ / "out/sub"));
  EXPECT_EQ(others(), "");
}

// Issue 40 §3: a previous output to which the user added a file is not the tool's to
// replace: refused naming the file, nothing touched (before: replaced whole, the file
// deleted). So is a folder shaped like a previous output without the marker, or with a
// marker of another kind, or a marker that is a link.
TEST_F(WholeFolderTest, PreviousOutputWithTheUsersFilesIsRefusedNamingOne) {
  write_previous(dir_ / "out");
  std::ofstream(dir_ / "out/sub/notes.txt") << "mine\n";
  try {
    WholeFolder folder(dir_ / "out", false, "test");
    FAIL() << "accepted a previous output holding the user's file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("out: cannot be written (a folder with other files: "
                                         "sub/notes.txt is not a file excite wrote, expected"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read(dir_ / "out/sub/notes.txt"), "mine\n");
  EXPECT_EQ(others(), "");

  fs::remove(dir_ / "out/sub/notes.txt");
  EXPECT_THROW(WholeFolder(dir_ / "out", false, "other kind"), std::runtime_error);
  fs::rename(dir_ / "out/.excite-output", dir_ / "marker-elsewhere");
  fs::create_symlink(dir_ / "marker-elsewhere", dir_ / "out/.excite-output");
  EXPECT_THROW(WholeFolder(dir_ / "out", false, "test"), std::runtime_error);
  fs::remove(dir_ / "out/.excite-output");
  EXPECT_THROW(WholeFolder(dir_ / "out", false, "test"), std::runtime_error);
  EXPECT_EQ(read(dir_ / "out/marker"), "old\n");
}

TEST_F(WholeFolderTest, WithoutCommitThePreviousFolderStaysAndNothingIsLeft) {
  write_previous(dir_ / "out");
  {
    WholeFolder folder(dir_ / "out", false, "test");
    std::ofstream(folder.staging() / "marker") << "half\n";
  }
  EXPECT_EQ(read(dir_ / "out/marker"), "old\n");
  EXPECT_EQ(others(), "");
}

TEST_F(WholeFolderTest, ForeignFolderOrFileIsRefusedUnlessOverwrite) {
  fs::create_directories(dir_ / "out");
  std::ofstream(dir_ / "out/mine.txt") << "mine\n";
  std::ofstream(dir_ / "file") << "x\n";
  try {
    WholeFolder folder(dir_ / "out", false, "test");
    FAIL() << "accepted a folder of other files";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("out: cannot be written (a folder with other files: no "
                                         ".excite-output of an excite test"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(WholeFolder(dir_ / "file", true, "test"), std::runtime_error);
  EXPECT_EQ(others(), "file ");
  WholeFolder folder(dir_ / "out", true, "test");
  folder.commit();
  EXPECT_FALSE(fs::exists(dir_ / "out/mine.txt"));
}

// A link to a folder: the folder it names is replaced, the link stays.
TEST_F(WholeFolderTest, LinkToAFolderIsFollowed) {
  fs::create_directories(dir_ / "real");
  fs::create_directory_symlink("real", dir_ / "out");
  WholeFolder folder(dir_ / "out", false, "test");
  std::ofstream(folder.staging() / "marker") << "new\n";
  folder.commit();
  EXPECT_TRUE(fs::is_symlink(dir_ / "out"));
  EXPECT_EQ(read(dir_ / "real/marker"), "new\n");
}

}  // namespace
