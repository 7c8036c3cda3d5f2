// SPDX-License-Identifier: MIT
// `excite import` and `excite identify` on real data as a process (issue 13 §1, issue 10 §6):
// a simulated run turned into a historian export — timestamps, absolute tag values, a gap,
// a `Bad` slice, a bad-quality MV sample, an offset and a drift on one CV — is imported
// (--detrend linear) and identified with the drift fitted with the model (--trend linear):
// within 3 points of fit and 6 % in every gain of the clean run.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.hpp"

namespace {

using excite_cli_test::excite;
using excite_cli_test::Result;

// A run log's data columns by name (the test's own reader: the format is the contract).
struct Columns {
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header_lines;
  std::size_t index(const std::string& name) const {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) return i;
    }
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};

Columns read_columns(const std::string& path) {
  std::ifstream in(path);
  Columns c;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      c.header_lines.push_back(line);
      continue;
    }
    std::vector<std::string> fields;
    std::stringstream s(line);
    std::string f;
    while (std::getline(s, f, ',')) fields.push_back(f);
    if (c.names.empty()) {
      c.names = fields;
    } else {
      c.rows.push_back(fields);
    }
  }
  return c;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::string iso(std::time_t t) {
  std::array<char, 32> buf{};
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(buf.data(), buf.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf.data();
}

void write(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

class ExciteImport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("excite_import_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  // A noisy woodberry2x2 PRBS run (the case study's noise).
  void simulate(const char* run, int seed) {
    if (!std::filesystem::exists(path("wb.plan"))) {
      ASSERT_EQ(
          excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code,
          0);
    }
    const Result sim =
        excite("simulate " + path("wb.plan") + " --plant woodberry2x2 --noise-var 5e-4 --seed " +
               std::to_string(seed) + " -o " + path(run));
    ASSERT_EQ(sim.exit_code, 0) << sim.out;
  }
  std::filesystem::path dir_;
};

TEST_F(ExciteImport, HistorianExportOfASimulatedRunIdentifiesLikeTheCleanRun) {
  simulate("clean.csv", 7);
  const Columns run = read_columns(path("clean.csv"));
  ASSERT_GT(run.rows.size(), 500U);
  const std::size_t du1 = run.index("du_u1"), du2 = run.index("du_u2");
  const std::size_t dy1 = run.index("dy_y1"), dy2 = run.index("dy_y2");
  const std::size_t N = run.rows.size();

  // The historian's view: absolute values around an operating point, ISO timestamps,
  // a quality column for the first MV.
  const std::time_t start = 1772352000;  // 2026-03-01T08:00:00Z
  const double base_u1 = 1.95, base_u2 = 1.71, base_y1 = 96.0, base_y2 = 0.5;
  const double drift_per_min = 0.3 / static_cast<double>(N);  // 0.3 over the run
  std::ostringstream h;
  h << "# exported from the plant historian\n";
  h << "Timestamp,FIC-101.SP,FIC-101.SP.quality,FIC-102.SP,AI-201.PV,AI-202.PV\n";
  // The export starts half an hour before the test, at the operating point (where the
  // baseline is taken); the run's row k is the export's row kPre + k.
  constexpr std::size_t kPre = 30;
  std::size_t gap_rows = 0, bad_rows = 0;
  h.precision(17);
  for (std::size_t e = 0; e < kPre + N; ++e) {
    const bool in_run = e >= kPre;
    const std::size_t k = in_run ? e - kPre : 0;
    if (in_run && k >= 300 && k < 305) {  // a gap: the historian recorded nothing for 5 min
      ++gap_rows;
      continue;
    }
    const auto value = [&](std::size_t column) {
      return in_run ? std::stod(run.rows[k][column]) : 0.0;
    };
    h << iso(start + static_cast<std::time_t>(60 * e)) << ',' << base_u1 + value(du1) << ','
      << (in_run && (k == 900 || k == 901) ? "0" : "192") << ',' << base_u2 + value(du2) << ',';
    if (in_run && k >= 600 && k < 610) {
      h << "Bad";  // a bad slice on the first CV
      ++bad_rows;
    } else {
      h << base_y1 + value(dy1);
    }
    h << ',' << base_y2 + 0.5 + drift_per_min * static_cast<double>(e) + value(dy2) << '\n';
  }
  write(path("historian.csv"), h.str());
  write(path("tags.toml"),
        "[[mv]]\ntag = \"FIC-101.SP\"\nname = \"u1\"\nunit = \"kg/min\"\n"
        "[[mv]]\ntag = \"FIC-102.SP\"\nname = \"u2\"\nunit = \"kg/min\"\n"
        "[[cv]]\ntag = \"AI-201.PV\"\nname = \"y1\"\nunit = \"mol%\"\n"
        "[[cv]]\ntag = \"AI-202.PV\"\nname = \"y2\"\nunit = \"mol%\"\n");

  // --tau-high: the test's design (woodberry2x2: τ_H = 21 min) travels in the run log's
  // header, where identify takes its time-constant bound β·τ_H from.
  const Result imp = excite("import " + path("historian.csv") + " --map " + path("tags.toml") +
                            " --detrend linear --tau-high 21 -o " + path("imported.csv"));
  ASSERT_EQ(imp.exit_code, 0) << imp.out;
  EXPECT_NE(imp.out.find("quality column used"), std::string::npos) << imp.out;
  const Columns imported = read_columns(path("imported.csv"));
  EXPECT_EQ(imported.rows.size(), kPre + N);  // the gap's rows are there, flagged
  bool units = false;
  for (const auto& l : imported.header_lines)
    units |= l == "# units: u1=kg/min u2=kg/min y1=mol% y2=mol%";
  EXPECT_TRUE(units) << "the tags' units are in the run log";
  int time_scales = 0;
  for (const auto& l : imported.header_lines)
    time_scales += (l == "# tau_high_min: 21") + (l == "# beta: 3");
  EXPECT_EQ(time_scales, 2) << "--tau-high and the default beta are in the run log";
  const std::size_t flags = imported.index("flags");
  std::size_t flagged_bad = 0, discontinuities = 0;
  for (const auto& r : imported.rows) {
    const unsigned f = static_cast<unsigned>(std::stoul(r[flags]));
    flagged_bad += (f & 128U) != 0U ? 1U : 0U;
    discontinuities += (f & 64U) != 0U ? 1U : 0U;
  }
  // The gap's first minute is held (the last sample is within 1.5 T), its other four are
  // bad; the Bad slice; the two bad-quality MV rows.
  EXPECT_EQ(flagged_bad, (gap_rows - 1) + bad_rows + 2);
  EXPECT_EQ(discontinuities, 2U);  // after the gap and after the bad MV rows

  ASSERT_EQ(excite("identify -o " + path("clean.json") + " " + path("clean.csv")).exit_code, 0);
  // The drift is fitted with the model (--trend linear: per segment, exact by projection);
  // import's least-squares line alone is biased by the response's own slow swings.
  const Result id =
      excite("identify --trend linear -o " + path("imported.json") + " " + path("imported.csv"));
  ASSERT_EQ(id.exit_code, 0) << id.out;
  EXPECT_NE(id.out.find("warning"), std::string::npos) << id.out;
  EXPECT_NE(id.out.find("16 flagged rows excluded (discontinuity 2, bad_value 16)"),
            std::string::npos)
      << id.out;
  EXPECT_NE(id.out.find("output y1 [mol%]"), std::string::npos) << id.out;
  const auto clean = read_json(path("clean.json"));
  const auto hist = read_json(path("imported.json"));
  EXPECT_EQ(hist["data"]["segments"].get<int>(), 3);
  for (std::size_t j = 0; j < 2; ++j) {
    const double fc = clean["outputs"][j]["fit"].get<double>();
    const double fh = hist["outputs"][j]["fit"].get<double>();
    std::printf("output %zu: fit clean %.2f %%, historian %.2f %%\n", j + 1, fc, fh);
    EXPECT_NEAR(fh, fc, 3.0) << "output " << j + 1;
    for (std::size_t i = 0; i < 2; ++i) {
      const double kc = clean["gain"][j][i].get<double>();
      const double kh = hist["gain"][j][i].get<double>();
      std::printf("  K(%zu,%zu): clean %.3f, historian %.3f\n", j + 1, i + 1, kc, kh);
      EXPECT_NEAR(kh, kc, 0.06 * std::abs(kc)) << "K(" << j + 1 << "," << i + 1 << ")";
    }
  }
}

TEST_F(ExciteImport, SeveralRunsAreIdentifiedTogether) {
  simulate("a.csv", 7);
  simulate("b.csv", 8);
  const Result id =
      excite("identify -o " + path("ab.json") + " " + path("a.csv") + " " + path("b.csv"));
  ASSERT_EQ(id.exit_code, 0) << id.out;
  const auto m = read_json(path("ab.json"));
  EXPECT_EQ(m["data"]["runs"].size(), 2U);
  EXPECT_EQ(m["data"]["segments"].get<int>(), 2);
  EXPECT_NEAR(m["gain"][0][0].get<double>(), 12.8, 0.5);
  EXPECT_NEAR(m["gain"][1][1].get<double>(), -19.4, 0.5);
}

struct BadHistorian {
  const char* what;
  const char* csv;
  const char* args;
  std::vector<std::string> expected;  // every one must be in the message
};

TEST_F(ExciteImport, BadHistorianInputIsRefusedNamingFileLineAndColumnOrTag) {
  const std::vector<BadHistorian> cases = {
      {"unknown tag",
       "time,A,B\n2026-03-01T08:00:00Z,1,2\n2026-03-01T08:01:00Z,1,2\n",
       "--mv A --cv C",
       {"h.csv:1", "tag = 'C'", "'time', 'A', 'B' (3 columns)"}},
      {"timestamps going back",
       "time,A,B\n2026-03-01T08:00:00Z,1,2\n2026-03-01T08:02:00Z,1,2\n2026-03-01T08:01:00Z,1,2\n",
       "--mv A --cv B",
       {"h.csv:4", "time = '2026-03-01T08:01:00Z'", "line 3", "strictly increasing"}},
      {"unparseable timestamp",
       "time,A,B\n2026-03-01T08:00:00Z,1,2\n01/03/2026 08:01,1,2\n",
       "--mv A --cv B",
       {"h.csv:3", "time = '01/03/2026 08:01'", "ISO 8601"}},
      {"no data rows", "time,A,B\n", "--mv A --cv B", {"h.csv:1", "data rows = 0"}},
      {"ragged row",
       "time,A,B\n1700000000,1,2\n1700000060,1\n",
       "--mv A --cv B",
       {"h.csv:3", "fields = 2, expected 3"}},
  };
  for (const auto& c : cases) {
    write(path("h.csv"), c.csv);
    std::filesystem::remove(path("out.csv"));
    const Result r = excite("import " + path("h.csv") + " " + c.args + " -o " + path("out.csv"));
    EXPECT_EQ(r.exit_code, 1) << c.what << ": " << r.out;
    for (const auto& e : c.expected) {
      EXPECT_NE(r.out.find(e), std::string::npos) << c.what << ": '" << e << "' not in " << r.out;
    }
    EXPECT_FALSE(std::filesystem::exists(path("out.csv"))) << c.what << ": nothing written";
  }
}

}  // namespace
