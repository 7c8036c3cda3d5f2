// SPDX-License-Identifier: MIT
// ReadOptions' limits (issue 38 §1): the row limit counted while reading, before any row is
// parsed; the value bound on every du and dy; neither when not asked.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "firmware/runlog/reader.hpp"

namespace excite::runlog {
namespace {

const std::string kHeader =
    "# excite run log v1\n"
    "# plant: column A\n"
    "# plan: plans/prbs.toml\n"
    "# sample_time_min: 0.5\n"
    "# inputs: L V\n"
    "# outputs: xD\n"
    "# units: L=kmol/min V=kmol/min xD=mol/mol\n";
const std::string kColumns = "t_min,k,du_L,du_V,u_L,u_V,dy_xD,flags\n";

std::string rows(int count, const std::string& du_v = "-0.1") {
  std::string s;
  for (int k = 0; k < count; ++k) {
    s += std::to_string(0.5 * k) + "," + std::to_string(k) + ",0.1," + (k == 2 ? du_v : "-0.1") +
         ",2.8,3.1," + std::to_string(0.01 * k) + ",0\n";
  }
  return s;
}

ReadOptions limited(std::size_t max_rows, double max_abs_value = 0.0) {
  ReadOptions o;
  o.max_rows = max_rows;
  o.max_abs_value = max_abs_value;
  o.limits_source = "host/README.md, Limits";
  return o;
}

TEST(RunLogReaderLimits, AtTheRowLimitReadsOneRowPastIsRefused) {
  EXPECT_TRUE(parse_run_log(kHeader + kColumns + rows(4), "run.csv", limited(4)).ok());
  const ReadResult r = parse_run_log(kHeader + kColumns + rows(5), "run.csv", limited(4));
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.over_row_limit);
  EXPECT_EQ(r.error->to_string(),
            "run.csv: more than 4 data rows, expected at most 4 (host/README.md, Limits)");
}

// The rows are counted before they are parsed: a log past the limit is refused for its
// length even when a row past the limit is malformed (it is never parsed).
TEST(RunLogReaderLimits, TheRowLimitComesBeforeAnyRowIsParsed) {
  const std::string text = kHeader + kColumns + rows(5) + "not,a,row\n";
  EXPECT_EQ(parse_run_log(text, "run.csv").error->message,
            "3 fields, expected 8 as in the column header row");
  EXPECT_TRUE(parse_run_log(text, "run.csv", limited(5)).over_row_limit);
}

TEST(RunLogReaderLimits, ReadRunLogCountsWhileReading) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "excite_reader_limits_test.csv";
  {
    std::ofstream out(path, std::ios::binary);
    out << kHeader << kColumns << rows(5);
    for (int i = 0; i < 20'000; ++i) out << "past the limit, never parsed\n";
  }
  const ReadResult r = read_run_log(path.string(), limited(4));
  std::filesystem::remove(path);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.over_row_limit);
  EXPECT_EQ(r.error->to_string(), path.string() +
                                      ": more than 4 data rows, expected at most 4 "
                                      "(host/README.md, Limits)");
}

TEST(RunLogReaderLimits, AValueBeyondTheBoundIsNamedByRowKAndColumn) {
  EXPECT_TRUE(parse_run_log(kHeader + kColumns + rows(4, "-1e12"), "run.csv", limited(10, 1e12))
                  .ok());
  const ReadResult r =
      parse_run_log(kHeader + kColumns + rows(4, "-2e12"), "run.csv", limited(10, 1e12));
  ASSERT_FALSE(r.ok());
  EXPECT_FALSE(r.over_row_limit);
  EXPECT_EQ(r.error->to_string(),
            "run.csv: data row 3 (k = 2), column du_V = -2e+12, expected |value| <= 1e+12");
}

TEST(RunLogReaderLimits, WithoutLimitsAnyLengthAndFiniteValueReads) {
  const ReadResult r = parse_run_log(kHeader + kColumns + rows(500, "1e300"), "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.rows(), 500U);
  EXPECT_EQ(r.log.du[1][2], 1e300);
}

}  // namespace
}  // namespace excite::runlog
