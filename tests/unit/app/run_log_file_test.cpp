// SPDX-License-Identifier: MIT
// The run log's file at start-up (firmware/app/run_log_file.hpp): a start-up that fails
// before the log's header leaves no file behind; from keep() on the file stays.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "firmware/app/run_log_file.hpp"

namespace excite::app {
namespace {

namespace fs = std::filesystem;

class RunLogFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("run_log_file_test." + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(RunLogFileTest, IsRemovedWhenStartUpFailsBeforeItIsKept) {
  const fs::path path = dir_ / "gw.csv";
  {
    RunLogFile log(path.string());
    ASSERT_TRUE(log.is_open());
    EXPECT_TRUE(fs::exists(path));
  }  // a refused arm: returned before keep()
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(RunLogFileTest, StaysWithWhatWasWrittenOnceKept) {
  const fs::path path = dir_ / "gw.csv";
  {
    RunLogFile log(path.string());
    log.keep();
    std::fputs("# header\n", log.get());
    EXPECT_TRUE(log.close());
    EXPECT_TRUE(log.close());  // once: a second close is a no-op
  }
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "# header");
}

TEST_F(RunLogFileTest, KeptFileIsClosedByTheDestructorAndStays) {
  const fs::path path = dir_ / "gw.csv";
  {
    RunLogFile log(path.string());
    log.keep();
    std::fputs("row\n", log.get());
  }  // a header that failed to write: the caller returns, the file stays
  EXPECT_EQ(fs::file_size(path), 4U);
}

TEST_F(RunLogFileTest, AFileThatCannotBeOpenedIsNotOpenAndNothingIsRemoved) {
  const fs::path other = dir_ / "other.csv";
  std::ofstream(other) << "someone else's";
  {
    RunLogFile log((dir_ / "no" / "such" / "folder.csv").string());
    EXPECT_FALSE(log.is_open());
    EXPECT_EQ(log.get(), nullptr);
  }
  EXPECT_TRUE(fs::exists(other));
}

}  // namespace
}  // namespace excite::app
