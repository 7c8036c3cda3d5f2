// SPDX-License-Identifier: MIT
// `excite import`: nothing misread silently, and bounded (issue 22). Each misread the issue
// found (exit 0 and wrong data) is here refused or read right; each bound (the run log's row
// and value limits, a line's length, a message's length) holds.

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

constexpr long long kStart = 1772352000;  // 2026-03-01T08:00:00Z

class ImportMisread : public ExciteCli {
 protected:
  // `rows` minutes of 1-min data A (MV), B (CV): epoch seconds.
  static std::string minutes(int rows) {
    std::string s = "Time,A,B\n";
    for (int k = 0; k < rows; ++k) {
      s += std::to_string(kStart + 60LL * k) + "," + std::to_string(1 + k % 3) + "," +
           std::to_string(k % 5) + "\n";
    }
    return s;
  }
  Result import(const std::string& csv, const std::string& options) {
    std::ofstream(path("h.csv")) << csv;
    std::filesystem::remove(path("out.csv"));
    return excite("import " + path("h.csv") + " " + options + " -o " + path("out.csv"));
  }
  bool written() const { return std::filesystem::exists(path("out.csv")); }
};

#define EXPECT_HAS(text, part) \
  EXPECT_NE((text).find(part), std::string::npos) << "'" << (part) << "' not in: " << (text)

TEST_F(ImportMisread, EpochMillisecondsAreRefusedWithoutEpochAndReadWithIt) {
  std::string csv = "t,A,B\n";
  for (int k = 0; k < 30; ++k) {
    csv += std::to_string((kStart + 60LL * k) * 1000) + "," + std::to_string(k % 2) + ",1\n";
  }
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:2: t = '1772352000000', expected epoch seconds");
  EXPECT_HAS(r.out, "its magnitude reads as ms since 1970");  // the magnitude named…
  EXPECT_HAS(r.out, "2026-03-01T08:00:00Z");
  EXPECT_HAS(r.out, "--epoch ms");  // …and the option, never a guess
  EXPECT_FALSE(written());
  const Result ms = import(csv, "--mv A --cv B --epoch ms");
  ASSERT_EQ(ms.exit_code, 0) << ms.out;
  EXPECT_HAS(ms.out, "30 samples of 1 min");
  const Result us = import(csv, "--mv A --cv B --epoch us");  // the wrong unit, said
  EXPECT_EQ(us.exit_code, 1) << us.out;
  EXPECT_HAS(us.out, "expected epoch us (--epoch); its magnitude reads as ms");
}

TEST_F(ImportMisread, RepeatedTimeColumnsGiveEachTagItsOwnTimes) {
  // PI "compressed": B sampled every minute, A only twice; B's values stay at B's times.
  std::string csv = "Time,A,Time,B\n";
  for (int k = 0; k < 10; ++k) {
    const std::string t = std::to_string(kStart + 60LL * k);
    csv += (k == 0 ? t + ",5" : (k == 1 ? std::to_string(kStart + 540) + ",6" : ",")) + "," + t +
           "," + std::to_string(10 * k) + "\n";
  }
  const Result r = import(csv, "--mv A --cv B --max-gap-min 10 --baseline 0:0");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_HAS(r.out, "10 samples of 1 min");
  const std::string log = bytes_of(path("out.csv"));
  // Row k = 9: A = 6 (its second sample), dy_B = 90 − 0.
  EXPECT_HAS(log, "\n9,9,1,6,90,");
}

TEST_F(ImportMisread, DuplicateColumnNamesAreRefusedUnlessAddressed) {
  const std::string csv = "Time,A,A,B\n0,1,2,3\n60,1,2,3\n120,1,4,3\n";
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:1: tag = 'A' (columns 2, 3), expected a unique column name");
  EXPECT_HAS(r.out, "'A#2'");
  const Result second = import(csv, "--mv 'A#2' --cv B");  // the run log names it A_2
  EXPECT_EQ(second.exit_code, 1) << second.out;            // '#' is no channel name…
  std::ofstream(path("map.toml")) << "[[mv]]\ntag = \"A#2\"\nname = \"A2\"\n[[cv]]\ntag = \"B\"\n";
  const Result mapped = import(csv, "--map " + path("map.toml"));  // …a map names it
  ASSERT_EQ(mapped.exit_code, 0) << mapped.out;
  EXPECT_HAS(bytes_of(path("out.csv")), "\n2,2,2,4,0,");  // the second A column: 4 at k = 2
}

TEST_F(ImportMisread, ThousandsSeparatorsAreReadAndBadCellsQuotedWithTheirLine) {
  const std::string csv =
      "Time,A,B\n0,\"1,001.5\",1\n60,\"1,002.5\",1\n120,\"1,00.5\",1\n180,Bad,1\n240,1003,1\n";
  const Result r = import(csv, "--mv A --cv B --baseline 0:0");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_HAS(r.out, "baseline 1001.5, 2 bad points");
  EXPECT_HAS(r.out, "2 bad cells, not numbers: line 4 '1,00.5' line 5 'Bad'");
}

TEST_F(ImportMisread, ConfidenceIsNotReadAsAnOpcQualityCode) {
  std::string csv = "Time,A,A.Quality,B\n";
  for (int k = 0; k < 10; ++k) {
    csv += std::to_string(kStart + 60LL * k) + "," + std::to_string(k) + ",100,1\n";
  }
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:2: quality of A = '100', expected 'good' or an OPC quality code");
  EXPECT_HAS(r.out, "--good-confidence");
  const Result c = import(csv, "--mv A --cv B --good-confidence 50");
  ASSERT_EQ(c.exit_code, 0) << c.out;
  EXPECT_HAS(c.out, "0 rows flagged bad_value");
  std::string conf = csv;
  conf.replace(conf.find("A.Quality"), 9, "A.Confidence");
  const Result named = import(conf, "--mv A --cv B");  // a confidence column needs the threshold
  EXPECT_EQ(named.exit_code, 1) << named.out;
  EXPECT_HAS(named.out, "column 'A.Confidence' = a 0–100 confidence, expected --good-confidence");
}

TEST_F(ImportMisread, ValuesBeyondTheRunLogLimitAreRefusedNamingLineAndTag) {
  const std::string csv = "Time,A,B\n0,1,2\n60,1,2e12\n120,1,2\n";
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:3: B = '2e12', expected |value| <= 5e+11");
  EXPECT_FALSE(written());
}

TEST_F(ImportMisread, MixedZonedAndNaiveTimestampsAreRefused) {
  const std::string csv =
      "Time,A,B\n2026-03-01T08:00:00Z,1,2\n2026-03-01T08:01:00,1,2\n2026-03-01T08:02:00Z,1,2\n";
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:3: Time = '2026-03-01T08:01:00', expected a time with a zone");
  EXPECT_HAS(r.out, "as on line 2");
}

TEST_F(ImportMisread, LocalTimesRepeatedOrSkippedByDaylightSavingAreRefusedByLine) {
  // Europe/Berlin: 2026-10-25 02:00–03:00 local happens twice; 2026-03-29 02:00–03:00 never.
  std::string autumn = "Time,A,B\n";
  for (const char* t : {"01:00", "01:30", "01:59"})
    autumn += "2026-10-25 " + std::string(t) + ":00,1,2\n";
  autumn += "2026-10-25 02:30:00,1,2\n";
  const Result r = import(autumn, "--mv A --cv B --time-zone Europe/Berlin");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:5: Time = '2026-10-25 02:30:00', expected an unambiguous local time");
  EXPECT_HAS(r.out, "2026-10-25T00:30:00Z or 2026-10-25T01:30:00Z");
  const Result spring = import("Time,A,B\n2026-03-29 01:30:00,1,2\n2026-03-29 02:30:00,1,2\n",
                               "--mv A --cv B --time-zone Europe/Berlin");
  EXPECT_EQ(spring.exit_code, 1) << spring.out;
  EXPECT_HAS(spring.out,
             "h.csv:3: Time = '2026-03-29 02:30:00', expected a local time of "
             "Europe/Berlin; the daylight-saving change skips it");
  const Result zone = import("Time,A,B\n0,1,2\n", "--mv A --cv B --time-zone Mars/Olympus");
  EXPECT_EQ(zone.exit_code, 1) << zone.out;
  EXPECT_HAS(zone.out, "--time-zone = Mars/Olympus, expected an IANA zone");
}

TEST_F(ImportMisread, AMistypedYearIsRefusedBeforeTheGridIsAllocated) {
  std::string csv = minutes(1440);
  csv += std::to_string(kStart + 36LL * 365 * 86400) + ",1,1\n";  // year 2062, line 1442
  const Result r = import(csv, "--mv A --cv B");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:1442: time = 2062-");
  EXPECT_HAS(r.out, "expected a record of at most 100000 rows of 1 min");
  EXPECT_HAS(r.out, "give --from/--to (a time window) or a longer --sample-time-min");
  EXPECT_FALSE(written());
  const Result window = import(csv, "--mv A --cv B --to 2026-03-02T07:59:00Z");
  ASSERT_EQ(window.exit_code, 0) << window.out;
  EXPECT_HAS(window.out, "1440 samples of 1 min");
}

TEST_F(ImportMisread, AYearOfMinutesIsRefusedWithAWindowHintAndReadInAWindow) {
  const Result r = import(minutes(120'000), "--mv A --cv B");  // 83 days of minutes
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "h.csv:120001: time = ");
  EXPECT_HAS(r.out, "120000 rows");
  EXPECT_HAS(r.out, "--from/--to");
  const Result w = import(minutes(120'000),
                          "--mv A --cv B --from 2026-03-11T08:00:00Z --to 2026-03-12T07:59:00Z");
  ASSERT_EQ(w.exit_code, 0) << w.out;
  EXPECT_HAS(w.out, "1440 samples of 1 min");
}

TEST_F(ImportMisread, AnEndlessLineIsRefusedInBoundedMemory) {
  const Result r = excite("import /dev/zero --mv A --cv B -o " + path("out.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_HAS(r.out, "/dev/zero:1: line longer than 62914560 bytes");
  EXPECT_LT(r.out.size(), 400U);
}

TEST_F(ImportMisread, AMissingTagNamesItAndAtMostTwentyColumns) {
  std::string header = "Time";
  for (int c = 0; c < 100'000; ++c) header += ",tag_" + std::to_string(c);
  const Result r = import(header + "\n", "--mv tag_1 --cv nowhere");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_HAS(r.out, "h.csv:1: tag = 'nowhere', expected a column of the header: 'Time', 'tag_0'");
  EXPECT_HAS(r.out, "'tag_18', … (100001 columns)");
  EXPECT_LT(r.out.size(), 600U) << r.out.size();
  // A huge column name and a huge cell are cut in a message too.
  const std::string name(100'000, 'T');
  const Result cell =
      import(name + ",A,B\n" + std::string(100'000, '7') + "x,1,2\n", "--mv A --cv B");
  EXPECT_EQ(cell.exit_code, 1);
  // (the 40 digits kept are shown short too, as every long number in a message: 7.77778e+39)
  EXPECT_HAS(cell.out, "h.csv:2: " + std::string(40, 'T') + "… = '7.77778e+39…'");
  EXPECT_LT(cell.out.size(), 600U) << cell.out.size();
}

}  // namespace
