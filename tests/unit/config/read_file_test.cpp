// SPDX-License-Identifier: MIT
// config::read_file (issue 40 §5): every configuration text is read whole only from a regular
// file within kMaxFileBytes; anything else is refused by name, without blocking on a FIFO or
// reading /dev/zero without end.
#include "base/config/document.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace excite::config {
namespace {

namespace fs = std::filesystem;

class ReadFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("excite_read_file_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The message read_file throws for `path`, or "read" when it reads it.
  static std::string refusal(const fs::path& path) {
    try {
      read_file(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "read";
  }
  fs::path dir_;
};

TEST_F(ReadFile, ReadsARegularFileWhole) {
  std::ofstream(dir_ / "a.toml") << "x = 1\n";
  EXPECT_EQ(read_file(dir_ / "a.toml"), "x = 1\n");
}

TEST_F(ReadFile, AFifoIsRefusedWithoutWaitingForAWriter) {
  const fs::path fifo = dir_ / "fifo.toml";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(refusal(fifo), fifo.string() + ": file type = FIFO, expected a regular file");
}

TEST_F(ReadFile, ADeviceOrAFolderIsRefusedByName) {
  EXPECT_EQ(refusal("/dev/zero"),
            "/dev/zero: file type = character device, expected a regular file");
  EXPECT_EQ(refusal(dir_), dir_.string() + ": file type = folder, expected a regular file");
}

TEST_F(ReadFile, AFileLargerThanTheBoundIsRefusedBeforeItIsRead) {
  const fs::path large = dir_ / "large.toml";
  std::ofstream(large).put('x');
  fs::resize_file(large, kMaxFileBytes + 1);  // sparse: no disk used
  EXPECT_EQ(refusal(large), large.string() + ": size = " + std::to_string(kMaxFileBytes + 1) +
                                " bytes, expected at most " + std::to_string(kMaxFileBytes) +
                                " bytes");
}

TEST_F(ReadFile, AMissingFileSaysWhy) {
  EXPECT_EQ(refusal(dir_ / "none.toml"),
            (dir_ / "none.toml").string() + ": cannot be read (No such file or directory)");
}

}  // namespace
}  // namespace excite::config
