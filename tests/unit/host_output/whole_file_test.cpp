// SPDX-License-Identifier: MIT
// host/output/whole_file.hpp: a file is replaced whole or not at all; a failure or an
// exception between opening and commit leaves the old file and no temporary file.

#include "host/output/whole_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using excite::host::WholeFile;
using excite::host::write_whole_file;

class WholeFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_whole_file_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string read(const fs::path& p) const {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  int entries() const {
    int n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }
  fs::path dir_;
};

TEST_F(WholeFileTest, NewFileAppearsOnlyAtCommit) {
  const fs::path p = dir_ / "new.txt";
  {
    WholeFile f(p);
    f.write("hello\n");
    EXPECT_FALSE(fs::exists(p));  // still the temporary file
    f.commit();
  }
  EXPECT_EQ(read(p), "hello\n");
  EXPECT_EQ(entries(), 1);
}

TEST_F(WholeFileTest, ExceptionBeforeCommitKeepsTheOldFileAndLeavesNoTemporary) {
  const fs::path p = dir_ / "old.txt";
  write_whole_file(p, "old\n");
  EXPECT_THROW(
      {
        WholeFile f(p);
        f.write("half of the new");
        throw std::runtime_error("the writer failed");
      },
      std::runtime_error);
  EXPECT_EQ(read(p), "old\n");
  EXPECT_EQ(entries(), 1);
}

TEST_F(WholeFileTest, MissingFolderIsAnErrorNamingThePath) {
  const fs::path p = dir_ / "no" / "such.txt";
  try {
    write_whole_file(p, "x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              p.string() + ": cannot be written (No such file or directory)");
  }
}

TEST_F(WholeFileTest, DanglingSymlinkCreatesItsTarget) {
  fs::create_symlink("target.txt", dir_ / "link.txt");
  write_whole_file(dir_ / "link.txt", "through the link\n");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link.txt")));
  EXPECT_EQ(read(dir_ / "target.txt"), "through the link\n");
}

TEST_F(WholeFileTest, DevNullIsWrittenThroughAndStaysADevice) {
  write_whole_file("/dev/null", "discarded\n");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

}  // namespace
