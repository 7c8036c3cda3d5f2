// SPDX-License-Identifier: MIT
// Issue 11 item 1: every output is written whole or not at all, and nothing the user did not
// name is replaced (host/README.md, "Output files"; host/output/whole_file.hpp).

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_process.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;
using excite_cli_test::shell;
namespace fs = std::filesystem;

// The names in the test's folder: no temporary file may be left behind.
std::string listing(const fs::path& dir) {
  std::string names;
  for (const auto& e : fs::directory_iterator(dir)) names += e.path().filename().string() + " ";
  return names;
}

bool is_character_device(const char* path) {
  struct stat st {};
  return ::stat(path, &st) == 0 && S_ISCHR(st.st_mode);
}

class OutputFiles : public ExciteCli {
 protected:
  // A 2×2 plan and its noisy run, the inputs of the commands below.
  void make_plan_and_run() {
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code,
        0);
    ASSERT_EQ(excite("simulate " + path("wb.plan") + " --plant woodberry2x2 --noise-var 5e-4 -o " +
                     path("wb.csv"))
                  .exit_code,
              0);
  }
};

// Run as root, `-o /dev/full` used to turn the device into a regular file.
TEST_F(OutputFiles, DevFullStaysADeviceAndEveryWriterFailsClearly) {
  ASSERT_TRUE(is_character_device("/dev/full"));
  make_plan_and_run();
  for (const std::string& command :
       {std::string("design -q --plant woodberry2x2 --preset prbsUnc -o /dev/full"),
        "simulate " + path("wb.plan") + " --plant woodberry2x2 -o /dev/full",
        "identify -o /dev/full " + path("wb.csv")}) {
    const Result r = excite(command);
    EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.out;
    EXPECT_NE(r.out.find("excite: error: /dev/full: cannot be written (No space left on device)"),
              std::string::npos)
        << command << "\n"
        << r.out;
    EXPECT_TRUE(is_character_device("/dev/full")) << command;
  }
}

// A symbolic link is followed: its target is replaced whole, the link stays a link.
TEST_F(OutputFiles, SymlinkIsFollowedAndItsTargetReplacedWhole) {
  // Byte-identical plans whatever the second they are made in (only for this test).
  struct FixedCreationTime {
    FixedCreationTime() { ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1); }
    ~FixedCreationTime() { ::unsetenv("SOURCE_DATE_EPOCH"); }
  } fixed_creation_time;
  ASSERT_EQ(
      excite("design -q --plant alatiqi4x4 --preset prbsUnc -o " + path("target.plan")).exit_code,
      0);
  fs::create_symlink("target.plan", path("link.plan"));
  ASSERT_EQ(
      excite("design -q --plant alatiqi4x4 --preset stepSeq -o " + path("link.plan")).exit_code, 0);
  ASSERT_EQ(
      excite("design -q --plant alatiqi4x4 --preset stepSeq -o " + path("direct.plan")).exit_code,
      0);
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("link.plan"))));
  EXPECT_EQ(bytes_of(path("target.plan")), bytes_of(path("direct.plan")));
  EXPECT_EQ(listing(dir_).size(), std::string("target.plan link.plan direct.plan ").size())
      << listing(dir_);
}

// A FIFO is written through (never replaced by a regular file), and so is "-" (stdout).
// The reader gives up after 20 s if the FIFO is never opened (replaced by a regular file).
TEST_F(OutputFiles, FifoAndStandardOutputAreWrittenThrough) {
  ASSERT_EQ(
      excite("design -q --plant alatiqi4x4 --preset prbsUnc -o " + path("file.plan")).exit_code, 0);
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  const Result r =
      shell("timeout 20 cat " + path("fifo") + " > " + path("copy.plan") + " & " +
            std::string(EXCITE_CLI) + " design -q --plant alatiqi4x4 --preset prbsUnc -o " +
            path("fifo") + "; status=$?; wait; exit $status");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  const std::string plan = bytes_of(path("file.plan"));
  EXPECT_EQ(bytes_of(path("copy.plan")).size(), plan.size());
  const Result out = excite("design -q --plant alatiqi4x4 --preset prbsUnc -o -");
  ASSERT_EQ(out.exit_code, 0);
  EXPECT_EQ(out.out.size(), plan.size());
  EXPECT_EQ(out.out.substr(0, 8), plan.substr(0, 8));  // magic and version; the rest has the time
}

// `ulimit -f` in a child shell: the write fails with the system's reason, the old file is
// intact and no temporary file is left (simulate streams its rows; identify writes JSON;
// design writes the encoded plan).
TEST_F(OutputFiles, FileSizeLimitLeavesTheOldFileIntactAndNoTemporaryFile) {
  make_plan_and_run();
  std::ofstream(path("run.csv")) << "old run\n";
  std::ofstream(path("model.json")) << "{\"old\": true}\n";
  const std::string before = listing(dir_);
  const Result sim = shell("ulimit -f 4; " + std::string(EXCITE_CLI) + " simulate " +
                           path("wb.plan") + " --plant woodberry2x2 -o " + path("run.csv"));
  EXPECT_EQ(sim.exit_code, 1) << sim.out;
  EXPECT_NE(sim.out.find(path("run.csv") + ": cannot be written (File too large)"),
            std::string::npos)
      << sim.out;
  EXPECT_EQ(bytes_of(path("run.csv")), "old run\n");
  const Result id = shell("ulimit -f 1; " + std::string(EXCITE_CLI) + " identify -o " +
                          path("model.json") + " " + path("wb.csv"));
  EXPECT_EQ(id.exit_code, 1) << id.out;
  EXPECT_NE(id.out.find(path("model.json") + ": cannot be written (File too large)"),
            std::string::npos)
      << id.out;
  EXPECT_EQ(bytes_of(path("model.json")), "{\"old\": true}\n");
  // A multisine plan (2.5 KB) under `ulimit -f 1` (512 B in dash, 1 KiB in bash) used to leave a 1
  // KiB PLAN.partial.
  const std::string plan_before = bytes_of(path("wb.plan"));
  const Result design =
      shell("ulimit -f 1; " + std::string(EXCITE_CLI) +
            " design -q --plant alatiqi4x4 --preset msSrdSim -o " + path("wb.plan"));
  EXPECT_EQ(design.exit_code, 1) << design.out;
  EXPECT_NE(design.out.find(path("wb.plan") + ": cannot be written (File too large)"),
            std::string::npos)
      << design.out;
  EXPECT_EQ(bytes_of(path("wb.plan")), plan_before);
  EXPECT_EQ(listing(dir_), before);
}

// An existing, longer file is replaced whole (no tail of the old one) and keeps its mode.
TEST_F(OutputFiles, ExistingFileIsReplacedWholeAndKeepsItsMode) {
  make_plan_and_run();
  std::ofstream(path("model.json")) << std::string(1 << 20, 'x');
  fs::permissions(path("model.json"),
                  fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_EQ(excite("identify -o " + path("model.json") + " " + path("wb.csv")).exit_code, 0);
  const std::string model = bytes_of(path("model.json"));
  EXPECT_LT(model.size(), 1U << 20);
  EXPECT_EQ(model.find('x' + std::string(64, 'x')), std::string::npos);
  EXPECT_NE(model.find("\"format\": \"excite model v2\""), std::string::npos);
  EXPECT_EQ(fs::status(path("model.json")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(OutputFiles, DirectoryAsOutputIsRefusedByName) {
  const Result r = excite("design -q --plant alatiqi4x4 --preset prbsUnc -o " + dir_.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(dir_.string() + ": cannot be written (it is a directory)"),
            std::string::npos)
      << r.out;
}

}  // namespace
