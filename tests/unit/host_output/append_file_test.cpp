// SPDX-License-Identifier: MIT
// host/output/append_file.hpp: every append is in the file when append() returns; an
// existing file or a link is refused and left as it was; a write error is an error.

#include "host/output/append_file.hpp"

#include <sys/resource.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using excite::host::AppendFile;

class AppendFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_append_file_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static std::string message_of(const fs::path& p) {
    try {
      AppendFile f(p);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

// A reader (the operator's tail -f, a crash) sees each append as soon as it returns.
TEST_F(AppendFileTest, EachAppendIsInTheFileWhenAppendReturns) {
  const fs::path p = dir_ / "decisions.jsonl";
  AppendFile f(p);
  EXPECT_EQ(read(p), "");
  f.append("{\"event\":\"segment\"}\n");
  EXPECT_EQ(read(p), "{\"event\":\"segment\"}\n");
  f.append("{\"event\":\"stop\"}\n");
  EXPECT_EQ(read(p), "{\"event\":\"segment\"}\n{\"event\":\"stop\"}\n");
}

TEST_F(AppendFileTest, AnExistingFileIsRefusedAndKept) {
  const fs::path p = dir_ / "decisions.jsonl";
  std::ofstream(p) << "an earlier record\n";
  EXPECT_EQ(message_of(p), p.string() + ": cannot be written (File exists)");
  EXPECT_EQ(read(p), "an earlier record\n");
}

// A planted link, even one to nothing, is not followed: nothing appears at its target.
TEST_F(AppendFileTest, ALinkIsRefusedAndItsTargetNotCreated) {
  const fs::path target = dir_ / "outside.txt";
  const fs::path p = dir_ / "decisions.jsonl";
  fs::create_symlink(target, p);
  EXPECT_EQ(message_of(p), p.string() + ": cannot be written (File exists)");
  EXPECT_FALSE(fs::exists(target));
}

// `ulimit -f`: the write that crosses the limit is an error naming the file, not a SIGXFSZ
// kill; what was appended before it stays.
TEST_F(AppendFileTest, AFileSizeLimitIsAWriteError) {
  const fs::path p = dir_ / "decisions.jsonl";
  AppendFile f(p);
  f.append("1234");
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit small = saved;
  small.rlim_cur = 8;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  try {
    f.append("56789abc");
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &saved), 0);
  EXPECT_EQ(message, p.string() + ": cannot be written (File too large)");
  EXPECT_EQ(read(p), "12345678");  // the short write kept what fitted
}

}  // namespace
