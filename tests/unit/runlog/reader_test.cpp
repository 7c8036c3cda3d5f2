// SPDX-License-Identifier: MIT
#include "firmware/runlog/reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

std::string rows(int count) {
  std::string s;
  for (int k = 0; k < count; ++k) {
    s += std::to_string(0.5 * k) + "," + std::to_string(k) + ",0.1,-0.1,2.8,3.1," +
         std::to_string(0.01 * k) + ",0\n";
  }
  return s;
}

ReadError error_of(const std::string& text, ReadOptions options = {}) {
  const ReadResult r = parse_run_log(text, "run.csv", options);
  EXPECT_FALSE(r.ok());
  return r.error.value_or(ReadError{});
}

TEST(RunLogReader, ReadsHeaderAndColumns) {
  const ReadResult r = parse_run_log(kHeader + kColumns + rows(4), "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.plant, "column A");
  EXPECT_EQ(r.log.plan, "plans/prbs.toml");
  EXPECT_EQ(r.log.sample_time_min, 0.5);
  ASSERT_EQ(r.log.input_names.size(), 2U);
  EXPECT_EQ(r.log.output_units[0], "mol/mol");
  ASSERT_EQ(r.log.rows(), 4U);
  EXPECT_EQ(r.log.t_min[3], 1.5);
  EXPECT_EQ(r.log.k[3], 3U);
  EXPECT_EQ(r.log.du[1][2], -0.1);
  EXPECT_EQ(r.log.u[0][0], 2.8);
  EXPECT_EQ(r.log.dy[0][3], 0.03);
}

// Found by tests/fuzz/runlog_reader_fuzz: a CR inside the producer's text was read, and the
// writer, which writes free text as one line without CR, could not write it back.
TEST(RunLogReader, CarriageReturnInsideHeaderTextIsRefused) {
  for (const std::string key : {"producer", "plant", "plan"}) {
    std::string header = kHeader;
    if (key == "producer") {
      header.insert(20, "# producer: excite simul\rte 0.1.0\n");
    } else {
      const auto at = header.find("# " + key + ": ");
      header.insert(at + key.size() + 4, "a\rb ");
    }
    const ReadError e = error_of(header + kColumns + rows(2));
    EXPECT_EQ(e.message,
              "header key '" + key + "' has a carriage return inside its text, expected one line")
        << key;
  }
  // CR LF line ends stay accepted
  std::string crlf = kHeader + kColumns + rows(2);
  for (std::size_t at = crlf.find('\n'); at != std::string::npos; at = crlf.find('\n', at + 2)) {
    crlf.insert(at, "\r");
  }
  EXPECT_TRUE(parse_run_log(crlf, "run.csv").ok());
}

TEST(RunLogReader, ALogWithoutProducerLineStillReads) {
  const ReadResult r = parse_run_log(kHeader + kColumns + rows(2), "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.producer, "");
  const ReadResult twice = parse_run_log("# excite run log v1\n# producer: a\n# producer: b\n" +
                                             kHeader.substr(20) + kColumns + rows(2),
                                         "run.csv");
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.error->message, "header key 'producer' given twice");
}

TEST(RunLogReader, AcceptsColumnsInAnyOrderAndCrLf) {
  std::string text = kHeader + "flags,dy_xD,u_V,u_L,du_V,du_L,k,t_min\r\n";
  text += "0,1.5,3,2,-1,-2,7,3.5\r\n0,1.25,3,2,-1,-2,8,4\r\n";
  const ReadResult r = parse_run_log(text, "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.du[0][0], -2.0);
  EXPECT_EQ(r.log.dy[0][1], 1.25);
  EXPECT_EQ(r.log.k[1], 8U);
}

TEST(RunLogReader, MissingColumnIsNamed) {
  const ReadError e = error_of(kHeader + "t_min,k,du_L,du_V,u_L,u_V,flags\n" + rows(0));
  EXPECT_EQ(e.line, 8U);
  EXPECT_NE(e.message.find("missing column 'dy_xD'"), std::string::npos) << e.message;
}

TEST(RunLogReader, UnexpectedColumnIsNamedWithItsPosition) {
  const ReadError e = error_of(kHeader + "t_min,k,du_L,du_V,u_L,u_W,dy_xD,flags\n");
  EXPECT_EQ(e.line, 8U);
  EXPECT_EQ(e.column, 6U);
  EXPECT_NE(e.message.find("'u_W'"), std::string::npos) << e.message;
}

TEST(RunLogReader, NonNumericFieldNamesLineAndColumn) {
  const std::string text = kHeader + kColumns + rows(2) + "1,2,0.1,abc,2.8,3.1,0,0\n";
  const ReadError e = error_of(text);
  EXPECT_EQ(e.line, 11U);
  EXPECT_EQ(e.column, 4U);
  EXPECT_EQ(e.to_string(), "run.csv:11: column 4: du_V = 'abc', expected a number");
}

TEST(RunLogReader, NanAndInfAreRejected) {
  for (const std::string bad : {"nan", "inf", "-inf", "1e999"}) {
    const std::string text = kHeader + kColumns + rows(1) + "0.5,1,0.1,0.2,2.8,3.1," + bad + ",0\n";
    const ReadError e = error_of(text);
    EXPECT_EQ(e.line, 10U) << bad;
    EXPECT_EQ(e.column, 7U) << bad;
    EXPECT_NE(e.message.find(", expected a finite number"), std::string::npos) << e.message;
  }
}

TEST(RunLogReader, NonUniformTimeIsRejectedWithTolerance) {
  // A step of 0.5 + 1e-9 min is within 1e-6·T; 0.5 + 1e-5 is not.
  std::string ok = kHeader + kColumns + "0,0,0,0,0,0,0,0\n0.500000001,1,0,0,0,0,0,0\n";
  EXPECT_TRUE(parse_run_log(ok, "run.csv").ok());
  std::string bad = kHeader + kColumns + "0,0,0,0,0,0,0,0\n0.50001,1,0,0,0,0,0,0\n";
  const ReadError e = error_of(bad);
  EXPECT_EQ(e.line, 10U);
  EXPECT_EQ(e.column, 1U);
  EXPECT_NE(e.message.find("expected the sample time 0.5"), std::string::npos) << e.message;
}

TEST(RunLogReader, SkippedSampleIndexIsRejected) {
  const std::string text = kHeader + kColumns + "0,0,0,0,0,0,0,0\n0.5,2,0,0,0,0,0,0\n";
  const ReadError e = error_of(text);
  EXPECT_EQ(e.column, 2U);
  EXPECT_NE(e.message.find("expected 1"), std::string::npos) << e.message;
}

TEST(RunLogReader, TooFewRows) {
  ReadOptions options;
  options.min_rows = 10;
  const ReadError e = error_of(kHeader + kColumns + rows(3), options);
  EXPECT_NE(e.message.find("3 data rows, expected at least 10"), std::string::npos);
}

TEST(RunLogReader, WrongFieldCount) {
  const ReadError e = error_of(kHeader + kColumns + "0,0,0,0,0,0,0\n");
  EXPECT_EQ(e.line, 9U);
  EXPECT_NE(e.message.find("7 fields, expected 8"), std::string::npos) << e.message;
}

TEST(RunLogReader, UnknownFlagBitsAreRejected) {
  const ReadError e = error_of(kHeader + kColumns + "0,0,0,0,0,0,0,64\n0.5,1,0,0,0,0,0,0\n");
  EXPECT_EQ(e.column, 8U);
  EXPECT_NE(e.message.find(", expected only the documented flag bits"), std::string::npos);
}

TEST(RunLogReader, HeaderProblemsAreExplained) {
  EXPECT_NE(error_of("a,b\n").message.find("expected '# excite run log v3' (or v2, v1, v4)"),
            std::string::npos);
  EXPECT_EQ(error_of("# excite run log v5\n").message,
            "unsupported version '# excite run log v5'; this reader reads v1 to v4");
  std::string no_units = kHeader.substr(0, kHeader.find("# units")) + kColumns;
  EXPECT_NE(error_of(no_units).message.find("no '# units:' line"), std::string::npos);
  std::string missing_unit = kHeader;
  missing_unit.replace(missing_unit.find(" xD=mol/mol"), 11, "");
  const ReadError e = error_of(missing_unit + kColumns);
  EXPECT_EQ(e.line, 7U);
  EXPECT_NE(e.message.find("no unit for channel 'xD'"), std::string::npos) << e.message;
  std::string bad_t = kHeader;
  bad_t.replace(bad_t.find("0.5"), 3, "-1");
  EXPECT_NE(error_of(bad_t + kColumns).message.find("sample_time_min is '-1'"), std::string::npos);
}

// ---- format v2: the state column and the v2 flags ----

const std::string kHeaderV2 = "# excite run log v2\n" + kHeader.substr(kHeader.find('\n') + 1);
const std::string kColumnsV2 = "t_min,k,du_L,du_V,u_L,u_V,dy_xD,flags,state\n";

TEST(RunLogReader, V1LogsReadWithUnknownState) {
  const ReadResult r = parse_run_log(kHeader + kColumns + rows(3), "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.format_version, 1);
  ASSERT_EQ(r.log.state.size(), 3U);
  for (const RunState s : r.log.state) EXPECT_EQ(s, RunState::unknown);
  // A v1 log has no state column: one is an unexpected column there.
  const ReadError e = error_of(kHeader + kColumnsV2);
  EXPECT_NE(e.message.find("unexpected column 'state'"), std::string::npos) << e.message;
}

TEST(RunLogReader, V2ReadsTheStateOfEveryRow) {
  const std::string text = kHeaderV2 + kColumnsV2 + "0,0,0,0,2.8,3.1,0,0,armed\n" +
                           "0.5,1,0.1,0,2.9,3.1,0,4,running\n" + "1,2,0,0,2.8,3.1,0,1,suspended\n" +
                           "1.5,3,0,0,2.8,3.1,0,0,safe_unconfirmed\n";
  const ReadResult r = parse_run_log(text, "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.format_version, 2);
  ASSERT_EQ(r.log.state.size(), 4U);
  EXPECT_EQ(r.log.state[0], RunState::armed);
  EXPECT_EQ(r.log.state[1], RunState::running);
  EXPECT_EQ(r.log.state[2], RunState::suspended);
  EXPECT_EQ(r.log.state[3], RunState::safe_unconfirmed);
}

// ---- format v3: the segment column ----

const std::string kHeaderV3 = "# excite run log v3\n" + kHeader.substr(kHeader.find('\n') + 1);
const std::string kColumnsV3 = "t_min,k,du_L,du_V,u_L,u_V,dy_xD,flags,state,segment\n";

TEST(RunLogReader, V3ReadsTheSegmentOfEveryRow) {
  const std::string text = kHeaderV3 + kColumnsV3 + "0,0,0,0,2.8,3.1,0,0,running,0\n" +
                           "0.5,1,0.1,0,2.9,3.1,0,0,running,1\n" +
                           "1,2,0,0,2.8,3.1,0,0,running,2\n";
  const ReadResult r = parse_run_log(text, "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.format_version, 3);
  EXPECT_EQ(r.log.segment, (std::vector<std::uint32_t>{0, 1, 2}));
}

TEST(RunLogReader, V1AndV2LogsReadWithSegmentZero) {
  const ReadResult v1 = parse_run_log(kHeader + kColumns + rows(3), "run.csv");
  ASSERT_TRUE(v1.ok()) << v1.error->to_string();
  EXPECT_EQ(v1.log.segment, (std::vector<std::uint32_t>{0, 0, 0}));
  const ReadResult v2 = parse_run_log(
      kHeaderV2 + kColumnsV2 + "0,0,0,0,2.8,3.1,0,0,armed\n0.5,1,0,0,2.8,3.1,0,0,running\n",
      "run.csv");
  ASSERT_TRUE(v2.ok()) << v2.error->to_string();
  EXPECT_EQ(v2.log.segment, (std::vector<std::uint32_t>{0, 0}));
  // A v2 log has no segment column; a v3 log must have one.
  EXPECT_NE(error_of(kHeaderV2 + kColumnsV3).message.find("unexpected column 'segment'"),
            std::string::npos);
  EXPECT_NE(error_of(kHeaderV3 + kColumnsV2).message.find("missing column 'segment'"),
            std::string::npos);
  const ReadError bad = error_of(kHeaderV3 + kColumnsV3 + "0,0,0,0,2.8,3.1,0,0,running,x\n");
  EXPECT_NE(bad.message.find("segment = 'x', expected a non-negative integer"), std::string::npos)
      << bad.message;
}

TEST(RunLogReader, V2RequiresAKnownStateInItsColumn) {
  const ReadError missing = error_of(kHeaderV2 + kColumns);
  EXPECT_NE(missing.message.find("missing column 'state'"), std::string::npos) << missing.message;
  const ReadError bad =
      error_of(kHeaderV2 + kColumnsV2 + "0,0,0,0,2.8,3.1,0,0,armed\n0.5,1,0,0,2.8,3.1,0,0,go\n");
  EXPECT_EQ(bad.line, 10U);
  EXPECT_EQ(bad.column, 9U);
  EXPECT_NE(bad.message.find("state = 'go', expected a run state: unknown, configured"),
            std::string::npos)
      << bad.message;
}

TEST(RunLogReader, V2FlagBitsAreKnownInV2OnlyAndBit8IsNot) {
  const std::string v2 = kHeaderV2 + kColumnsV2 + "0,0,0,0,0,0,0,0,running\n" +
                         "0.5,1,0,0,0,0,0,192,running\n";  // discontinuity | bad_value
  const ReadResult r = parse_run_log(v2, "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.flags[1], kDiscontinuity | kBadValue);
  const ReadError v1 = error_of(kHeader + kColumns + "0,0,0,0,0,0,0,0\n0.5,1,0,0,0,0,0,64\n");
  EXPECT_NE(v1.message.find(", expected only the documented flag bits (v1: suspended=1"),
            std::string::npos)
      << v1.message;
  const ReadError bit8 =
      error_of(kHeaderV2 + kColumnsV2 + "0,0,0,0,0,0,0,256,running\n0.5,1,0,0,0,0,0,0,running\n");
  EXPECT_NE(bit8.message.find("skipped=32, discontinuity=64, bad_value=128"), std::string::npos)
      << bit8.message;
}

TEST(RunLogReader, V2SkippedRowJumpsKAndTimeTogether) {
  // Ticks 2 and 3 were missed: the row after them is k = 4, t = 2 min, flagged skipped (32).
  const std::string head =
      kHeaderV2 + kColumnsV2 + "0,0,0,0,0,0,0,0,running\n" + "0.5,1,0,0,0,0,0,0,running\n";
  const ReadResult r = parse_run_log(head + "2,4,0,0,0,0,0,32,running\n", "run.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.k[2], 4U);
  // The same jump without the flag is an error, as in v1.
  const ReadError unflagged = error_of(head + "2,4,0,0,0,0,0,0,running\n");
  EXPECT_NE(unflagged.message.find("k: 4 follows 1, expected 2"), std::string::npos)
      << unflagged.message;
  // Flagged skipped, k and t_min must still agree.
  const ReadError time = error_of(head + "1.5,4,0,0,0,0,0,32,running\n");
  EXPECT_EQ(time.column, 1U);
  EXPECT_NE(time.message.find("expected 1.5 min (3 ticks"), std::string::npos) << time.message;
  // A skipped flag with no tick skipped says something that is not so.
  const ReadError none = error_of(head + "1,2,0,0,0,0,0,32,running\n");
  EXPECT_NE(none.message.find("expected more than 2 (the row is flagged skipped)"),
            std::string::npos)
      << none.message;
}

TEST(RunLogReader, MissingFileIsAnError) {
  const ReadResult r = read_run_log("/nonexistent/run.csv");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error->to_string().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace excite::runlog
