// SPDX-License-Identifier: MIT
// Issue 40 §2: `excite montecarlo merge` trusts nothing a shard's folder says. A real run's
// folder (woodberry2x2, two designs, two seeds: a second) is copied and one thing in it
// planted per case; merge must refuse it naming the file and the field, and write nothing:
// a design name that is markup or a path, another plant over woodberry units, a seed count
// that once asked for 1.5 GB, a FIFO (merge once hung), /dev/zero, a unit file over the
// size bound, values a run never writes. And `merge -o OUT` writes only its own entries
// (summary.json, index.html, figures/), never over the user's files nor through a link.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../host_cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::Result;

const char* const kShardRun =
    "montecarlo --plant woodberry2x2 --designs prbsUnc,prbsSimDir --seeds 2 --length-step 50 "
    "--threads 2";

class MergeTrust : public excite_cli_test::ExciteCli {
 protected:
  // One real run for the whole suite, copied per test.
  static void SetUpTestSuite() {
    source_ = fs::temp_directory_path() / ("excite_merge_trust_" + std::to_string(::getpid()));
    fs::remove_all(source_);
    const Result r = excite(std::string(kShardRun) + " -o " + source_.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
  }
  static void TearDownTestSuite() { fs::remove_all(source_); }

  // A copy of the run as a shard folder to plant into.
  fs::path shard() {
    const fs::path s = dir_ / "shard";
    fs::copy(source_, s, fs::copy_options::recursive);
    for (const char* made : {"summary.json", "index.html", "figures"}) fs::remove_all(s / made);
    return s;
  }
  static nlohmann::json read(const fs::path& file) {
    return nlohmann::json::parse(bytes_of(file.string()));
  }
  static void write(const fs::path& file, const nlohmann::json& j) {
    std::ofstream(file) << j.dump(1) << "\n";
  }
  // merge of the shard into OUT, bounded in time: a merge that waits on a FIFO fails.
  Result merge(const std::string& extra = "") {
    return excite_cli_test::shell("timeout 60 " + std::string(EXCITE_CLI) + " montecarlo merge " +
                                  path("shard") + " -o " + path("out") + " " + extra);
  }
  // merge refuses, naming `message`, and writes no report.
  void expect_refused(const std::string& message) {
    const Result r = merge();
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "out/index.html")) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "out/summary.json")) << r.out;
  }

  static fs::path source_;
};

fs::path MergeTrust::source_;

TEST_F(MergeTrust, TheRunAsWrittenMerges) {
  shard();
  const Result r = merge();
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(bytes_of(path("out/summary.json")), bytes_of((source_ / "summary.json").string()));
  EXPECT_EQ(bytes_of(path("out/index.html")), bytes_of((source_ / "index.html").string()));
}

// A design name that is markup (it once ran as a script in index.html) or a path: only
// the design library's names are designs.
TEST_F(MergeTrust, DesignNamesOutsideTheLibraryAreRefused) {
  const fs::path s = shard();
  nlohmann::json run = read(s / "run.json");
  run["designs"][0] = "<script>document.title='pwned'</script>";
  fs::rename(s / "units/prbsUnc", s / "units/script");
  write(s / "run.json", run);
  expect_refused("shard/run.json: designs = [\"<script>document.title='pwned'</script>\"");
  run["designs"][0] = "../../elsewhere";
  write(s / "run.json", run);
  expect_refused(
      "designs = [\"../../elsewhere\",\"prbsSimDir\"], expected an array of design "
      "names from: ");
  run["designs"] = {"prbsSimDir", "prbsUnc"};  // not in Table order: units numbered otherwise
  write(s / "run.json", run);
  expect_refused(
      "designs = [\"prbsSimDir\",\"prbsUnc\"], expected Table 6.1 acronyms in Table "
      "order, each once");
}

TEST_F(MergeTrust, AnotherPlantOverTheUnitsIsRefused) {
  const fs::path s = shard();
  nlohmann::json run = read(s / "run.json");
  run["plant"] = "alatiqi4x4";
  write(s / "run.json", run);
  expect_refused("seed-1.json: singular_values = 2 values, expected 4 (alatiqi4x4) or none");
  run["plant"] = "no-such-plant";
  write(s / "run.json", run);
  expect_refused("shard/run.json: plant = \"no-such-plant\", expected one of");
}

// 2e9 seeds once asked for 1.5 GB of units (std::bad_alloc).
TEST_F(MergeTrust, SeedCountsAndGridsOutOfRangeAreRefusedBeforeAnyWork) {
  const fs::path s = shard();
  nlohmann::json run = read(s / "run.json");
  run["seeds"] = 2000000000;
  write(s / "run.json", run);
  expect_refused("shard/run.json: seeds = 2000000000, expected an integer from 1 to 1000000");
  run["seeds"] = 2;
  run["length_step_percent"] = -5;
  write(s / "run.json", run);
  expect_refused("length_step_percent = -5, expected an integer from 0 to 100");
}

// A FIFO (merge once waited on it for ever), /dev/zero (read until memory ran out) and a
// file over the bound are refused by what they are, naming the file.
TEST_F(MergeTrust, UnitFilesMustBeRegularFilesOfBoundedSize) {
  const fs::path s = shard();
  const fs::path unit = s / "units/prbsUnc/seed-1.json";
  fs::remove(unit);
  ASSERT_EQ(::mkfifo(unit.c_str(), 0600), 0);
  expect_refused("prbsUnc/seed-1.json: file type = FIFO, expected a regular file");
  fs::remove(unit);
  fs::create_symlink("/dev/zero", unit);
  expect_refused("prbsUnc/seed-1.json: file type = character device, expected a regular file");
  fs::remove(unit);
  std::ofstream(unit) << std::string(2 << 20, ' ') << "{}";
  expect_refused("prbsUnc/seed-1.json: size = 2097154 bytes, expected at most 1048576 bytes");
}

// Values a run never writes: each named with its file and field.
TEST_F(MergeTrust, UnitValuesOutOfRangeAreRefusedNamingTheField) {
  const fs::path s = shard();
  const fs::path unit = s / "units/prbsSimDir/seed-2.json";
  const nlohmann::json good = read(unit);
  const auto planted = [&](const char* pointer, const nlohmann::json& value) {
    nlohmann::json u = good;
    u[nlohmann::json::json_pointer(pointer)] = value;
    write(unit, u);
  };
  planted("/accuracy/weakest_angle_deg", 400.0);
  expect_refused("seed-2.json: accuracy.weakest_angle_deg = 400.0, expected 0 to 90 (degrees)");
  planted("/lengths/0/percent", 7);
  expect_refused("seed-2.json: lengths[0].percent = 7, expected 50");
  planted("/lengths/1/samples", 1000000);
  expect_refused("seed-2.json: lengths[1].samples = 1000000, expected 0 to the unit's 945");
  planted("/samples", -3);
  expect_refused("seed-2.json: samples = -3, expected 1 to 100000000");
  planted("/number", 5);
  expect_refused("seed-2.json: number = 5, expected 6 (Table 6.1's for prbsSimDir)");
  planted("/singular_values", nlohmann::json::array({1.0, 2.0, 3.0}));
  expect_refused("seed-2.json: singular_values = 3 values, expected 2 (woodberry2x2) or none");
  planted("/seed", 1);
  expect_refused("seed-2.json: design, seed = \"prbsSimDir\", 1, expected \"prbsSimDir\", 2");
}

// merge -o OUT: OUT's index.html, summary.json or figures/ that excite did not write are
// refused (they were replaced), a link planted at figures/ is never written through, and
// anything else in OUT (the shards, Slurm's logs) is kept. A previous merge is replaced.
TEST_F(MergeTrust, OutputFolderKeepsTheUsersFilesAndFollowsNoLink) {
  shard();
  fs::create_directories(dir_ / "out/logs");
  std::ofstream(path("out/index.html")) << "the user's page\n";
  std::ofstream(path("out/logs/merge.out")) << "slurm\n";
  Result r = merge();
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("out: cannot be written (index.html is not a file excite wrote, expected "),
            std::string::npos)
      << r.out;
  EXPECT_EQ(bytes_of(path("out/index.html")), "the user's page\n");
  fs::remove(path("out/index.html"));

  fs::create_directories(dir_ / "elsewhere");
  fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "out/figures");
  r = merge();
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("figures is not a file excite wrote"), std::string::npos) << r.out;
  r = merge("--overwrite");  // the link itself is replaced, never written through
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(fs::is_empty(dir_ / "elsewhere"));
  EXPECT_FALSE(fs::is_symlink(dir_ / "out/figures"));
  EXPECT_TRUE(fs::exists(dir_ / "out/figures/t90.svg"));
  EXPECT_EQ(bytes_of(path("out/logs/merge.out")), "slurm\n");

  r = merge();  // a previous merge's output: replaced
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ofstream(path("out/figures/notes.txt")) << "mine\n";
  r = merge();
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("figures/notes.txt is not a file excite wrote"), std::string::npos) << r.out;
  EXPECT_EQ(bytes_of(path("out/figures/notes.txt")), "mine\n");
  for (const auto& e : fs::directory_iterator(dir_ / "out"))
    EXPECT_NE(e.path().filename().string().rfind(".excite-montecarlo", 0), 0U) << e.path();
}

// Issue 40 §5: a unit file cut short blocked every resume (counted as done, then unreadable
// at the summary) with no hint; it is now run again, and said. Two processes on one folder
// ran the same units twice; the second is now refused naming the first.
TEST_F(MergeTrust, AResumeRedoesAUnitCutShortAndOneProcessHoldsTheFolder) {
  const fs::path s = shard();
  const fs::path unit = s / "units/prbsUnc/seed-1.json";
  const std::string whole = bytes_of(unit.string());
  std::ofstream(unit) << whole.substr(0, 100);
  Result r = excite(std::string(kShardRun) + " -o " + s.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("montecarlo: run again, its file does not read back: " + unit.string() +
                       ": text = not JSON"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(bytes_of(unit.string()), whole);  // the same unit, run again
  EXPECT_EQ(bytes_of((s / "summary.json").string()), bytes_of((source_ / "summary.json").string()));

  // Another process holds the folder (here: this test, as excite would).
  const int fd = ::open(s.c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  fs::remove(unit);
  r = excite(std::string(kShardRun) + " -o " + s.string());
  ::close(fd);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find(s.string() + ": locked = by another process, expected one excite "
                                    "montecarlo per folder"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(unit)) << "the refused process ran a unit";
}

}  // namespace
