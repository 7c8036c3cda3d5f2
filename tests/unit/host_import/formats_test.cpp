// SPDX-License-Identifier: MIT
// The export's formats (host/import, issue 22): numbers in either locale, strftime-style
// timestamps, IANA zones across daylight-saving changes, bounded lines, the layouts.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "host/import/csv_text.hpp"
#include "host/import/historian_csv.hpp"
#include "host/import/number_text.hpp"
#include "host/import/time_zone.hpp"
#include "host/import/timestamp.hpp"

namespace excite::host::historian {
namespace {

CsvOptions long_format() {
  CsvOptions o;
  o.long_format = true;
  return o;
}
CsvOptions pairs_format() {
  CsvOptions o;
  o.time_column_per_tag = true;
  return o;
}
CsvOptions european_with_units() {
  CsvOptions o;
  o.delimiter = ';';
  o.decimal_comma = true;
  o.header_rows = 2;
  return o;
}

TEST(NumberText, DecimalPointOrCommaWithGroupingInThrees) {
  EXPECT_EQ(parse_number("1,001.5", false), 1001.5);
  EXPECT_EQ(parse_number("12,345,678", false), 12345678.0);
  EXPECT_EQ(parse_number("-1.5e3", false), -1500.0);
  EXPECT_EQ(parse_number("+2", false), 2.0);
  EXPECT_EQ(parse_number("1.001,5", true), 1001.5);
  EXPECT_EQ(parse_number("-0,25", true), -0.25);
  EXPECT_EQ(parse_number("1,5e3", true), 1500.0);
  for (const char* bad : {"", "1,5", "1,00.5", "1,0001", ",100", "1,", "1.5.3", "nan", "inf", "Bad",
                          "0x10", "1 000", "1.5,3"}) {
    EXPECT_FALSE(parse_number(bad, false).has_value()) << bad;
  }
  for (const char* bad : {"1.5", "1.00,5", "1,5,3"}) {
    EXPECT_FALSE(parse_number(bad, true).has_value()) << bad;
  }
}

TEST(Timestamp, VendorFormsWithAStrftimeStyleFormat) {
  const double t = 1772352000.0;  // 2026-03-01T08:00:00Z
  EXPECT_EQ(parse_formatted("3/1/2026 8:00:00 AM", "%m/%d/%Y %I:%M:%S %p")->seconds, t);
  EXPECT_EQ(parse_formatted("3/1/2026 8:00:00 PM", "%m/%d/%Y %I:%M:%S %p")->seconds, t + 12 * 3600);
  EXPECT_EQ(parse_formatted("3/1/2026 12:00:00 AM", "%m/%d/%Y %I:%M:%S %p")->seconds, t - 8 * 3600);
  EXPECT_EQ(parse_formatted("01-Mar-26 08:00:00", "%d-%b-%y %H:%M:%S")->seconds, t);
  EXPECT_EQ(parse_formatted("01-MARCH-26 08:00:00", "%d-%b-%y %H:%M:%S")->seconds, t);
  EXPECT_EQ(parse_formatted("01.03.2026 08:00", "%d.%m.%Y %H:%M")->seconds, t);
  EXPECT_NEAR(parse_formatted("01-Mar-26 08:00:00.5", "%d-%b-%y %H:%M:%S")->seconds, t + 0.5, 1e-9);
  const auto zoned = parse_formatted("2026-03-01 09:00:00+01:00", "%F %T%z");
  ASSERT_TRUE(zoned.has_value());
  EXPECT_EQ(zoned->seconds, t);
  EXPECT_TRUE(zoned->zoned);
  EXPECT_FALSE(parse_formatted("01.03.2026 08:00", "%d.%m.%Y %H:%M")->zoned);
  for (const char* bad : {"13/1/2026 8:00:00 AM", "2/29/2026 8:00:00 AM", "3/1/2026 13:00:00 PM",
                          "3/1/2026 8:00:00", "3/1/2026 8:00:00 AM x"}) {
    EXPECT_FALSE(parse_formatted(bad, "%m/%d/%Y %I:%M:%S %p").has_value()) << bad;
  }
  EXPECT_EQ(check_time_format("%m/%d/%Y %I:%M:%S %p"), "");
  EXPECT_NE(check_time_format("%m/%d/%Y %I:%M"), "");  // %I without %p
  EXPECT_NE(check_time_format("%H:%M"), "");           // no date
  EXPECT_NE(check_time_format("%Y-%m-%d %H:%M %Q"), "");
  EXPECT_EQ(format_utc(t), "2026-03-01T08:00:00Z");
  EXPECT_EQ(format_utc(-1.0), "1969-12-31T23:59:59Z");
}

TEST(TimeZone, DaylightSavingChangesSkipAndRepeatLocalTimes) {
  const TimeZone berlin("Europe/Berlin");
  const double spring = *parse_timestamp("2026-03-29T00:00:00Z");  // local midnight + 1 h
  // 01:30 local (CET, +1) is 00:30Z; 02:30 is skipped; 03:30 (CEST, +2) is 01:30Z.
  EXPECT_EQ(berlin.to_utc(spring + 1.5 * 3600).utc_s, spring + 0.5 * 3600);
  EXPECT_EQ(berlin.to_utc(spring + 2.5 * 3600).status, TimeZone::Local::skipped);
  EXPECT_EQ(berlin.to_utc(spring + 3.5 * 3600).utc_s, spring + 1.5 * 3600);
  // 2026-10-25 02:30 local happens at 00:30Z (CEST) and at 01:30Z (CET).
  const double autumn = *parse_timestamp("2026-10-25T00:00:00Z");
  const TimeZone::Result r = berlin.to_utc(autumn + 2.5 * 3600);
  EXPECT_EQ(r.status, TimeZone::Local::ambiguous);
  EXPECT_EQ(r.utc_s, autumn + 0.5 * 3600);
  EXPECT_EQ(r.later_s, autumn + 1.5 * 3600);
  EXPECT_THROW(TimeZone("Europe/Atlantis"), std::invalid_argument);
  EXPECT_THROW(TimeZone("../etc/passwd"), std::invalid_argument);
}

TEST(CsvText, LinesAreBoundedAndMessagesShort) {
  std::istringstream in("a,b\r\n" + std::string(100, 'x') + "\n");
  LineReader lines(in, "f.csv", 50);
  std::string line;
  ASSERT_TRUE(lines.next(line));
  EXPECT_EQ(line, "a,b");
  try {
    (void)lines.next(line);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("f.csv:2: line longer than 50 bytes"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(split("\"1;5\"; 2 ;", ';'), (std::vector<std::string>{"1;5", "2", ""}));
  EXPECT_EQ(quote_cell(std::string(100, 'y')), "'" + std::string(40, 'y') + "…'");
}

TEST(HistorianCsv, LongFormatAndPerTagTimeColumns) {
  const HistorianData longf = parse_historian(
      "Tag,Time,Value\nA,0,1\nB,0,5\nA,60,2\nX,0,9\nB,120,6\n", "l.csv", {"A", "B"}, long_format());
  EXPECT_EQ(longf.series[0].time_s, (std::vector<double>{0, 60}));
  EXPECT_EQ(longf.series[1].time_s, (std::vector<double>{0, 120}));
  EXPECT_EQ(longf.series[1].values, (std::vector<double>{5, 6}));
  EXPECT_EQ(longf.series[1].line, (std::vector<std::size_t>{3, 6}));
  const HistorianData pairs =
      parse_historian("tA,A,tB,B\n0,1,30,7\n60,2,,\n", "p.csv", {"B", "A"}, pairs_format());
  EXPECT_EQ(pairs.series[0].time_s, (std::vector<double>{30}));
  EXPECT_EQ(pairs.series[1].time_s, (std::vector<double>{0, 60}));
}

TEST(HistorianCsv, UnitsRowAndBadCellExamples) {
  const HistorianData d =
      parse_historian("T;A;B\nEU;kg/h;degC\nDesc;x;y\n0;1,5;x\n60;2,5;\n120;3;y\n180;4;z\n",
                      "u.csv", {"A", "B"}, european_with_units());
  EXPECT_EQ(d.units, (std::vector<std::string>{"kg/h", "degC"}));
  EXPECT_EQ(d.units_line, 2U);
  EXPECT_EQ(d.series[0].values, (std::vector<double>{1.5, 2.5, 3, 4}));
  EXPECT_EQ(d.bad_cells[1], 4U);
  ASSERT_EQ(d.bad_examples[1].size(), 3U);  // the first three, with their lines
  EXPECT_EQ(d.bad_examples[1][1].line, 5U);
  EXPECT_EQ(d.bad_examples[1][1].text, "");
}

}  // namespace
}  // namespace excite::host::historian
