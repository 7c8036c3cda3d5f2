// SPDX-License-Identifier: MIT
// `excite import` on historian exports as they come (issue 22): a vendor corpus made here —
// the same record (an MV around 1000 with a thousands separator's worth of digits, a CV, a
// bad MV sample and a bad CV sample) written in ten shapes of real exports — must import
// with the options host/import/README.md names for each to the same run log as the ISO 8601
// original, row for row. None of the shapes is copied from a vendor.

#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

constexpr int kRows = 300;
constexpr int kBadA = 50;   // the MV's bad sample
constexpr int kBadB = 120;  // the CV's bad sample

// 2026-03-29T00:00:00Z: Europe/Berlin leaves CET for CEST at 01:00Z that day.
std::time_t start() {
  std::tm tm{};
  tm.tm_year = 2026 - 1900;
  tm.tm_mon = 2;
  tm.tm_mday = 29;
  return timegm(&tm);
}

std::time_t time_of(int k) {
  return start() + 60 * k;
}
double a_of(int k) {
  return 1000.5 + (k % 10 < 5 ? 1.25 : -1.25);
}
double b_of(int k) {
  return 0.5 + 0.001 * k + 0.01 * (k % 7);
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string utc(std::time_t t, const char* format) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  return buf;
}

// Local wall-clock time of `zone` (the C library's localtime, the other way round from
// the importer's local → UTC).
std::string local(std::time_t t, const char* zone, const char* format) {
  const char* old = std::getenv("TZ");
  const std::string saved = old != nullptr ? old : "";
  setenv("TZ", zone, 1);
  tzset();
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  if (old != nullptr) {
    setenv("TZ", saved.c_str(), 1);
  } else {
    unsetenv("TZ");
  }
  tzset();
  return buf;
}

// "1,001.750": a thousands separator in threes.
std::string grouped(double v, char group, char point) {
  std::string s = fmt("%.3f", v);
  const std::size_t dot = s.find('.');
  std::string whole = s.substr(0, dot);
  std::string out;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    if (i > 0 && (whole.size() - i) % 3 == 0) out += group;
    out += whole[i];
  }
  return out + point + s.substr(dot + 1);
}

std::string a_text(int k) {
  return fmt("%.3f", a_of(k));
}
std::string b_text(int k) {
  return fmt("%.4f", b_of(k));
}

struct Shape {
  const char* name;
  std::string csv;
  std::string options;
};

std::string iso_original() {
  std::string s = "Time,A,B\n";
  for (int k = 0; k < kRows; ++k) {
    s += utc(time_of(k), "%Y-%m-%dT%H:%M:%SZ") + "," + (k == kBadA ? "Bad" : a_text(k)) + "," +
         (k == kBadB ? "Bad" : b_text(k)) + "\n";
  }
  return s;
}

std::vector<Shape> corpus() {
  std::vector<Shape> shapes;
  {  // PI DataLink in a US Excel sheet: 12-hour clock, thousands separators, quoted.
    std::string s = "Timestamp,A,B\n";
    for (int k = 0; k < kRows; ++k) {
      std::string t = utc(time_of(k), "%m/%d/%Y %I:%M:%S %p");
      if (t[0] == '0') t.erase(0, 1);  // 3/29/2026 12:00:00 AM: no leading zeros
      if (t[t.find('/') + 1] == '0') t.erase(t.find('/') + 1, 1);
      if (t[t.find(' ') + 1] == '0') t.erase(t.find(' ') + 1, 1);
      s += "\"" + t + "\",\"" + (k == kBadA ? "I/O Timeout" : grouped(a_of(k), ',', '.')) + "\"," +
           (k == kBadB ? "#N/A" : b_text(k)) + "\n";
    }
    shapes.push_back({"pi_datalink_us", s, "--time-format '%m/%d/%Y %I:%M:%S %p'"});
  }
  {  // PI DataLink, day-month-name-year.
    std::string s = "Time,A,B\n";
    for (int k = 0; k < kRows; ++k) {
      s += utc(time_of(k), "%d-%b-%y %H:%M:%S") + "," + (k == kBadA ? "Bad Input" : a_text(k)) +
           "," + (k == kBadB ? "Bad Input" : b_text(k)) + "\n";
    }
    shapes.push_back({"pi_datalink_dmy", s, "--time-format '%d-%b-%y %H:%M:%S'"});
  }
  {  // PI archive, compressed: per-tag time columns of the same name; A stored only when it
     // changes (and around its bad sample), B every minute.
    std::vector<int> a_samples;
    for (int k = 0; k < kRows; ++k) {
      if (k == 0 || a_of(k) != a_of(k - 1) || k == kBadA || k == kBadA + 1 || k == kRows - 1) {
        a_samples.push_back(k);
      }
    }
    std::string s = "Time,A,Time,B\n";
    for (int k = 0; k < kRows; ++k) {
      const auto i = static_cast<std::size_t>(k);
      if (i < a_samples.size()) {
        const int ka = a_samples[i];
        s += utc(time_of(ka), "%Y-%m-%d %H:%M:%S") + "," + (ka == kBadA ? "Bad" : a_text(ka));
      } else {
        s += ",";
      }
      s += "," + utc(time_of(k), "%Y-%m-%d %H:%M:%S") + "," + (k == kBadB ? "Bad" : b_text(k)) +
           "\n";
    }
    shapes.push_back({"pi_archive_compressed", s, "--max-gap-min 10"});
  }
  {  // PI archive dump, TIME,VALUE pairs named per tag.
    std::string s = "A Time,A,B Time,B\n";
    for (int k = 0; k < kRows; ++k) {
      const std::string t = utc(time_of(k), "%Y-%m-%dT%H:%M:%SZ");
      s += t + "," + (k == kBadA ? "Shutdown" : a_text(k)) + "," + t + "," +
           (k == kBadB ? "Shutdown" : b_text(k)) + "\n";
    }
    shapes.push_back({"pi_archive_pairs", s, "--time-column-per-tag"});
  }
  {  // IP.21 Excel add-in: units and description rows under the header.
    std::string s = "TS,A,B\nUnits,kg/h,degC\nDescription,Reflux flow,Top temperature\n";
    for (int k = 0; k < kRows; ++k) {
      s += utc(time_of(k), "%d-%b-%y %H:%M:%S") + ".0," + (k == kBadA ? "" : a_text(k)) + "," +
           (k == kBadB ? "" : b_text(k)) + "\n";
    }
    shapes.push_back({"ip21_units_rows", s, "--header-rows 2 --time-format '%d-%b-%y %H:%M:%S'"});
  }
  {  // A German Excel export ("CSV UTF-8": a byte order mark first): semicolons, decimal
     // comma, thousands points.
    std::string s = "\xEF\xBB\xBFZeitstempel;A;B\n";
    for (int k = 0; k < kRows; ++k) {
      std::string b = b_text(k);
      b[b.find('.')] = ',';
      s += utc(time_of(k), "%d.%m.%Y %H:%M") + ";" +
           (k == kBadA ? "Fehler" : grouped(a_of(k), '.', ',')) + ";" +
           (k == kBadB ? "Fehler" : b) + "\n";
    }
    shapes.push_back(
        {"excel_de", s,
         "--delimiter ';' --decimal-comma --time-format '%d.%m.%Y %H:%M' --time-column "
         "Zeitstempel"});
  }
  {  // PHD: a 0–100 confidence column per tag; the bad samples carry numbers, confidence 0.
    std::string s = "Time,A,A.Confidence,B,B.Confidence\n";
    for (int k = 0; k < kRows; ++k) {
      s += utc(time_of(k), "%Y-%m-%dT%H:%M:%SZ") + "," + a_text(k) + "," +
           (k == kBadA ? "0" : "100") + "," + b_text(k) + "," + (k == kBadB ? "0" : "100") + "\n";
    }
    shapes.push_back({"phd_confidence", s, "--good-confidence 50"});
  }
  {  // Epoch milliseconds.
    std::string s = "t_ms,A,B\n";
    for (int k = 0; k < kRows; ++k) {
      s += std::to_string(static_cast<long long>(time_of(k)) * 1000) + "," +
           (k == kBadA ? "NaN" : a_text(k)) + "," + (k == kBadB ? "NaN" : b_text(k)) + "\n";
    }
    shapes.push_back({"epoch_ms", s, "--epoch ms"});
  }
  {  // Long format, OPC quality text; the bad samples carry numbers with quality Bad.
    std::string s = "Tag,Time,Value,Quality\n";
    for (int k = 0; k < kRows; ++k) {
      const std::string t = utc(time_of(k), "%Y-%m-%dT%H:%M:%SZ");
      s += "A," + t + "," + a_text(k) + "," + (k == kBadA ? "Bad" : "Good") + "\n";
      s += "C," + t + ",7,Good\n";  // a tag not asked for
      s += "B," + t + "," + b_text(k) + "," + (k == kBadB ? "Bad" : "Good") + "\n";
    }
    shapes.push_back({"long_quality", s, "--long"});
  }
  {  // DeltaV / Experion Excel in plant local time, across the spring daylight-saving change.
    std::string s = "Date Time,A,B\n";
    for (int k = 0; k < kRows; ++k) {
      s += local(time_of(k), "Europe/Berlin", "%d/%m/%Y %H:%M:%S") + "," +
           (k == kBadA ? "Comm Fail" : a_text(k)) + "," + (k == kBadB ? "Comm Fail" : b_text(k)) +
           "\n";
    }
    shapes.push_back(
        {"experion_local", s, "--time-format '%d/%m/%Y %H:%M:%S' --time-zone Europe/Berlin"});
  }
  return shapes;
}

// The run log's lines that are not `#` comments (the column header and the data rows).
std::vector<std::string> data_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out.push_back(line);
  }
  return out;
}

class ImportCorpus : public ExciteCli {
 protected:
  Result import(const std::string& name, const std::string& csv, const std::string& options) {
    const std::string in = path((name + ".csv").c_str());
    std::ofstream(in) << csv;
    return excite("import " + in + " --mv A --cv B " + options + " -o " +
                  path((name + ".run.csv").c_str()));
  }
  std::string run_log(const std::string& name) {
    return bytes_of(path((name + ".run.csv").c_str()));
  }
};

TEST_F(ImportCorpus, TenVendorShapesImportToTheIsoOriginalsRunLogRowForRow) {
  const Result iso = import("iso", iso_original(), "");
  ASSERT_EQ(iso.exit_code, 0) << iso.out;
  const std::vector<std::string> expected = data_lines(run_log("iso"));
  ASSERT_EQ(expected.size(), static_cast<std::size_t>(kRows) + 1) << iso.out;
  EXPECT_NE(iso.out.find("2 rows flagged bad_value"), std::string::npos) << iso.out;
  const std::vector<Shape> shapes = corpus();
  ASSERT_EQ(shapes.size(), 10U);
  for (const Shape& s : shapes) {
    const Result r = import(s.name, s.csv, s.options);
    ASSERT_EQ(r.exit_code, 0) << s.name << ": " << r.out;
    const std::vector<std::string> got = data_lines(run_log(s.name));
    ASSERT_EQ(got.size(), expected.size()) << s.name << ": " << r.out;
    for (std::size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got[i], expected[i]) << s.name << ": run log line " << i + 1 << "\n" << r.out;
    }
  }
  // The IP.21 units row gives the channels' units.
  EXPECT_NE(run_log("ip21_units_rows").find("# units: A=kg/h B=degC"), std::string::npos);
}

}  // namespace
