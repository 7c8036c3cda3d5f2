// SPDX-License-Identifier: MIT
#include "host/design/plan_file.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"

namespace excite::host {
namespace {

class PlanFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("excite_plan_file_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static std::vector<char> bytes_of(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  std::filesystem::path dir_;
};

TEST_F(PlanFile, IsReadBackIdenticallyAndRewrittenToTheSameBytes) {
  const Design d =
      design_preset(case_study("alatiqi4x4"), find_preset("prbsDirCorrSim"), 1700000000);
  const auto path = dir_ / "a.plan";
  write_plan_file(*d.plan, path);
  const auto back = read_plan_file(path);
  write_plan_file(*back, dir_ / "b.plan");
  EXPECT_EQ(bytes_of(path), bytes_of(dir_ / "b.plan"));
  EXPECT_EQ(back->meta.created_unix_s, 1700000000U);
  EXPECT_EQ(plan::text_of(back->meta.design_name), "prbsDirCorrSim");
  EXPECT_EQ(make_table(back->recipe), d.table);
}

// The gateway produces its table from the file's recipe at start-up, in blocks, with the
// same signal core: what it streams must be bit for bit what the host designed.
TEST_F(PlanFile, GatewayTableFromTheFileIsBitIdenticalToTheHostTable) {
  for (const PresetInfo& preset : presets()) {
    const Design d = design_preset(case_study("alatiqi4x4"), preset, 0);
    write_plan_file(*d.plan, dir_ / "p.plan");
    const auto loaded = read_plan_file(dir_ / "p.plan");
    const signal::Recipe& r = loaded->recipe;
    std::vector<double> streamed(std::size_t{r.samples} * r.channels);
    std::vector<double> scratch(signal::scratch_size(r));
    constexpr std::uint32_t kBlock = 256;
    for (std::uint32_t first = 0; first < r.samples; first += kBlock) {
      const std::uint32_t count = std::min(kBlock, r.samples - first);
      const signal::TableView block{streamed.data() + std::size_t{first} * r.channels, r.channels,
                                    count};
      ASSERT_TRUE(signal::generate_block(r, first, block, scratch).is_ok()) << preset.acronym;
    }
    ASSERT_EQ(streamed.size(), static_cast<std::size_t>(d.table.size()));
    EXPECT_EQ(std::memcmp(streamed.data(), d.table.data(), streamed.size() * sizeof(double)), 0)
        << preset.acronym;
  }
}

TEST_F(PlanFile, TruncatedFileIsRefusedNamingThePath) {
  const Design d = design_preset(case_study("alatiqi4x4"), find_preset("stepSeq"), 0);
  const auto path = dir_ / "t.plan";
  write_plan_file(*d.plan, path);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 3);
  try {
    read_plan_file(path);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST_F(PlanFile, MissingFileIsRefused) {
  EXPECT_THROW(read_plan_file(dir_ / "none.plan"), std::invalid_argument);
}

// Issue 40 §5: a plan is read whole only when it is a regular file no larger than the largest
// plan; anything else is refused by name, without blocking or reading without end.
TEST_F(PlanFile, OnlyARegularFileNoLargerThanTheLargestPlanIsRead) {
  const auto refusal = [](const std::filesystem::path& path) {
    try {
      read_plan_file(path);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  const auto fifo = dir_ / "fifo.plan";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(refusal(fifo).find(fifo.string() + ": file type = FIFO, expected a regular file"),
            std::string::npos)
      << refusal(fifo);
  EXPECT_NE(refusal("/dev/zero").find("/dev/zero: file type = character device"), std::string::npos)
      << refusal("/dev/zero");
  EXPECT_NE(refusal(dir_).find("is a directory, expected a plan file"), std::string::npos)
      << refusal(dir_);
  const auto large = dir_ / "large.plan";
  std::ofstream(large).put('x');
  std::filesystem::resize_file(large, plan::max_encoded_size() + 1);  // sparse: no disk used
  EXPECT_NE(refusal(large).find("size = " + std::to_string(plan::max_encoded_size() + 1) +
                                " bytes, expected at most"),
            std::string::npos)
      << refusal(large);
}

}  // namespace
}  // namespace excite::host
