// SPDX-License-Identifier: MIT
// ReadOptions' limits (issue 38 §1): the row limit counted while reading, before any row is
// parsed; the value bound on every du and dy; neither when not asked.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::runlog {
namespace {

// A two-input, one-output log as the writer writes it (format v3): `count` rows, row 2's du_V
// replaced by `du_v`, then `tail` (lines past the rows).
std::string log_text(int count, double du_v = -0.1, const std::string& tail = "") {
  const Channel inputs[] = {{"L", "kmol/min"}, {"V", "kmol/min"}};
  const Channel outputs[] = {{"xD", "mol/mol"}};
  Header header;
  header.plant = "column A";
  header.plan = "plans/prbs.toml";
  header.sample_time_min = 0.5;
  header.inputs = inputs;
  header.outputs = outputs;
  std::string text(4096, '\0');
  text.resize(format_header(header, text).length);
  for (int k = 0; k < count; ++k) {
    const double du[] = {0.1, k == 2 ? du_v : -0.1};
    const double u[] = {2.8, 3.1};
    const double dy[] = {0.01 * k};
    Row row;
    row.t_min = 0.5 * k;
    row.k = static_cast<std::uint64_t>(k);
    row.du = du;
    row.u = u;
    row.dy = dy;
    row.state = RunState::running;
    char line[max_row_chars(2, 1)];
    text.append(line, format_row(header, row, line).length);
  }
  return text + tail;
}

ReadOptions limited(std::size_t max_rows, double max_abs_value = 0.0) {
  ReadOptions o;
  o.max_rows = max_rows;
  o.max_abs_value = max_abs_value;
  o.limits_source = "host/README.md, Limits";
  return o;
}

TEST(RunLogReaderLimits, AtTheRowLimitReadsOneRowPastIsRefused) {
  EXPECT_TRUE(parse_run_log(log_text(4), "run.csv", limited(4)).ok());
  const ReadResult r = parse_run_log(log_text(5), "run.csv", limited(4));
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.over_row_limit);
  EXPECT_EQ(r.error->to_string(),
            "run.csv: more than 4 data rows, expected at most 4 (host/README.md, Limits)");
}

// The rows are counted before they are parsed: a log past the limit is refused for its
// length even when a row past the limit is malformed (it is never parsed).
TEST(RunLogReaderLimits, TheRowLimitComesBeforeAnyRowIsParsed) {
  const std::string text = log_text(5, -0.1, "not,a,row\n");
  EXPECT_EQ(parse_run_log(text, "run.csv").error->message,
            "3 fields, expected 10 as in the column header row");
  EXPECT_TRUE(parse_run_log(text, "run.csv", limited(5)).over_row_limit);
}

TEST(RunLogReaderLimits, ReadRunLogCountsWhileReading) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "excite_reader_limits_test.csv";
  {
    std::ofstream out(path, std::ios::binary);
    out << log_text(5);
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
  EXPECT_TRUE(parse_run_log(log_text(4, -1e12), "run.csv", limited(10, 1e12)).ok());
  const ReadResult r = parse_run_log(log_text(4, -2e12), "run.csv", limited(10, 1e12));
  ASSERT_FALSE(r.ok());
  EXPECT_FALSE(r.over_row_limit);
  EXPECT_EQ(r.error->to_string(),
            "run.csv: data row 3 (k = 2), column du_V = -2e+12, expected |value| <= 1e+12");
}

TEST(RunLogReaderLimits, WithoutLimitsAnyLengthAndFiniteValueReads) {
  const ReadResult r = parse_run_log(log_text(500, 1e300), "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.rows(), 500U);
  EXPECT_EQ(r.log.du[1][2], 1e300);
}

}  // namespace
}  // namespace excite::runlog
