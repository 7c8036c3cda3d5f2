// SPDX-License-Identifier: MIT
// Historian export → run log pieces (host/import): timestamps, the CSV reader's bad values
// and quality column, resampling that never bridges a gap, baseline, detrend and flags.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "firmware/runlog/format.hpp"
#include "host/import/historian_csv.hpp"
#include "host/import/import_run.hpp"
#include "host/import/resample.hpp"
#include "host/import/tag_map.hpp"
#include "host/import/timestamp.hpp"

namespace excite::host::historian {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Timestamp, IsoWithAndWithoutZoneAndEpochSeconds) {
  EXPECT_EQ(parse_timestamp("1970-01-01T00:00:00Z"), 0.0);
  EXPECT_EQ(parse_timestamp("2026-03-01T08:00:00Z"), 1772352000.0);
  EXPECT_EQ(parse_timestamp("2026-03-01 08:00:00"), 1772352000.0);  // no zone: as given
  EXPECT_EQ(parse_timestamp("2026-03-01T09:30:00+01:30"), 1772352000.0);
  EXPECT_EQ(parse_timestamp("2026-03-01T03:00:00-0500"), 1772352000.0);
  EXPECT_EQ(parse_timestamp("2026-03-01T08:00Z"), 1772352000.0);
  EXPECT_NEAR(*parse_timestamp("2026-03-01T08:00:00.25Z"), 1772352000.25, 1e-6);
  EXPECT_EQ(parse_timestamp("2024-02-29T00:00:00Z"), 1709164800.0);  // leap day
  EXPECT_EQ(parse_timestamp("1772352000"), 1772352000.0);
  EXPECT_EQ(parse_timestamp("1772352000.5"), 1772352000.5);
  for (const char* bad :
       {"", "2026-02-29T00:00:00Z", "2026-13-01T00:00:00Z", "2026-03-01", "2026-03-01T24:00:00",
        "01/03/2026 08:00", "2026-03-01T08:00:00Q", "nan", "12abc"}) {
    EXPECT_FALSE(parse_timestamp(bad).has_value()) << bad;
  }
}

TEST(HistorianCsv, BadValuesQualityAndQuotedFields) {
  const HistorianData d = parse_historian(
      "# comment\n"
      "\"Time\",\"A\",A.Quality,B\n"
      "1000,1.5,Good,\"2\"\n"
      "1060,Bad,Good,NaN\n"
      "1120,2.5,0,\n"
      "1180,3.5,192,#N/A\n",
      "h.csv", {"B", "A"});
  ASSERT_EQ(d.series[0].time_s.size(), 4U);
  const std::vector<double>& b = d.series[0].values;
  const std::vector<double>& a = d.series[1].values;
  EXPECT_EQ(b[0], 2.0);
  for (std::size_t k = 1; k < 4; ++k) EXPECT_TRUE(std::isnan(b[k]));
  EXPECT_EQ(a[0], 1.5);
  EXPECT_TRUE(std::isnan(a[1]));  // text
  EXPECT_TRUE(std::isnan(a[2]));  // bad quality
  EXPECT_EQ(a[3], 3.5);           // OPC 192: good
  EXPECT_EQ(d.bad_cells[0], 3U);
  EXPECT_EQ(d.bad_cells[1], 2U);
  EXPECT_FALSE(d.has_quality[0]);
  EXPECT_TRUE(d.has_quality[1]);
}

TEST(Resample, HoldAndLinearNeverBridgeAGap) {
  const std::vector<double> t = {0, 60, 120, 360, 420};  // a gap from 120 to 360 s
  const std::vector<double> v = {0, 1, 2, 5, kNaN};
  const std::vector<double> grid = {0, 30, 60, 90, 120, 180, 240, 300, 360, 390, 420};
  const std::vector<double> hold = resample(t, v, grid, Resample::hold, 90.0);
  const std::vector<double> hold_expected = {0, 0, 1, 1, 2, 2, kNaN, kNaN, 5, 5, kNaN};
  const std::vector<double> lin = resample(t, v, grid, Resample::linear, 90.0);
  const std::vector<double> lin_expected = {0, 0.5, 1, 1.5, 2, kNaN, kNaN, kNaN, 5, kNaN, kNaN};
  for (std::size_t k = 0; k < grid.size(); ++k) {
    if (std::isnan(hold_expected[k])) {
      EXPECT_TRUE(std::isnan(hold[k])) << "hold at " << grid[k];
    } else {
      EXPECT_DOUBLE_EQ(hold[k], hold_expected[k]) << "hold at " << grid[k];
    }
    if (std::isnan(lin_expected[k])) {
      EXPECT_TRUE(std::isnan(lin[k])) << "linear at " << grid[k];
    } else {
      EXPECT_DOUBLE_EQ(lin[k], lin_expected[k]) << "linear at " << grid[k];
    }
  }
}

HistorianData ramp_data(std::size_t n) {
  HistorianData d;
  d.file = "h.csv";
  d.series.resize(2);
  for (std::size_t k = 0; k < n; ++k) {
    for (TagSeries& s : d.series) {
      s.time_s.push_back(60.0 * static_cast<double>(k));
      s.line.push_back(k + 2);
    }
    d.series[0].values.push_back(k % 10 < 5 ? 3.0 : 4.0);                      // MV: square
    d.series[1].values.push_back(10.0 + 0.5 + 0.01 * static_cast<double>(k));  // CV: drift
  }
  d.bad_cells.assign(2, 0);
  d.has_quality.assign(2, false);
  return d;
}

ImportOptions two_tags() {
  ImportOptions o;
  o.baseline_auto = false;  // the window 0 … 0: the first sample (the auto rule: below)
  o.mvs = {{"FIC", "L", "kmol/min"}};
  o.cvs = {{"AI", "xD", "mol/mol"}};
  return o;
}

TEST(ImportRun, BaselineDeviationsAndLinearDetrend) {
  ImportOptions o = two_tags();
  o.detrend = Detrend::linear;
  const ImportedRun r = import_historian(ramp_data(100), o);
  ASSERT_EQ(r.rows(), 100U);
  EXPECT_DOUBLE_EQ(r.sample_time_min, 1.0);  // the timestamps' spacing
  EXPECT_EQ(r.input_baseline[0], 3.0);
  EXPECT_EQ(r.du[0][7], 1.0);
  EXPECT_EQ(r.u[0][7], 4.0);
  EXPECT_NEAR(r.removed_slope_per_min[0], 0.01, 1e-12);
  for (const double v : r.dy[0]) EXPECT_NEAR(v, 0.0, 1e-9);
  for (const std::uint32_t f : r.flags) EXPECT_EQ(f, 0U);
}

TEST(ImportRun, BaselineWindowIsTheMeanOfItsGoodValues) {
  ImportOptions o = two_tags();
  o.baseline_from_min = 0.0;
  o.baseline_to_min = 9.0;  // one whole period of the square wave
  const ImportedRun r = import_historian(ramp_data(100), o);
  EXPECT_DOUBLE_EQ(r.input_baseline[0], 3.5);
}

TEST(ImportRun, BadCvValueIsFlaggedAndHeldAndBadMvEndsInADiscontinuity) {
  HistorianData d = ramp_data(40);
  d.series[1].values[10] = kNaN;  // a bad CV sample
  d.series[0].values[20] = kNaN;  // two bad MV samples
  d.series[0].values[21] = kNaN;
  const ImportedRun r = import_historian(d, two_tags());
  EXPECT_EQ(r.flags[10], static_cast<std::uint32_t>(runlog::kBadValue));
  EXPECT_EQ(r.dy[0][10], r.dy[0][9]);  // held, never interpolated
  EXPECT_EQ(r.flags[20], static_cast<std::uint32_t>(runlog::kBadValue));
  EXPECT_EQ(r.flags[21], static_cast<std::uint32_t>(runlog::kBadValue));
  EXPECT_EQ(r.flags[22], static_cast<std::uint32_t>(runlog::kDiscontinuity));
  EXPECT_EQ(r.bad_rows, 3U);
  EXPECT_EQ(r.discontinuities, 1U);
  EXPECT_EQ(r.bad_points[0], 2U);
  EXPECT_EQ(r.bad_points[1], 1U);
  const std::string text = run_log_text(r, "h.csv");
  EXPECT_NE(text.find("# units: L=kmol/min xD=mol/mol"), std::string::npos);
  EXPECT_NE(text.find("# plant: historian h.csv"), std::string::npos);
}

TEST(ImportRun, RefusalsNameTheTagAndWhatWasExpected) {
  ImportOptions o = two_tags();
  o.cvs[0].name = "x D";
  try {
    (void)import_historian(ramp_data(10), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tag 'AI'"), std::string::npos) << e.what();
  }
  HistorianData d = ramp_data(10);
  d.series[1].values[0] = kNaN;  // no good CV value at the first grid point: no baseline
  try {
    (void)import_historian(d, two_tags());
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tag 'AI' has no good value"), std::string::npos)
        << e.what();
  }
}

TEST(TagMap, RolesNamesUnitsAndUnknownKeys) {
  const TagMap m = parse_tag_map(
      "[[mv]]\ntag = \"FIC-101.SP\"\nname = \"L\"\nunit = \"kmol/min\"\n[[cv]]\ntag = \"AI\"\n",
      "tags.toml");
  ASSERT_EQ(m.mvs.size(), 1U);
  EXPECT_EQ(m.mvs[0].name, "L");
  EXPECT_EQ(m.cvs[0].name, "AI");
  EXPECT_EQ(m.cvs[0].unit, "-");
  try {
    (void)parse_tag_map("[[mv]]\ntag = \"A\"\nunits = \"x\"\n", "tags.toml");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tags.toml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mv[1].units"), std::string::npos) << e.what();
  }
}

// --baseline auto (issue 18 §2): a steady window before the first MV move gives the
// baselines; a record whose MVs move (or whose CVs drift) before τ_H has no such window.
std::vector<std::vector<double>> mv_cv(std::size_t rows, std::size_t first_move, double drift) {
  std::vector<std::vector<double>> v(2, std::vector<double>(rows));
  for (std::size_t k = 0; k < rows; ++k) {
    v[0][k] = k < first_move ? 3.0 : (k / 7 % 2 == 0 ? 4.0 : 2.0);
    v[1][k] = 10.0 + drift * static_cast<double>(k) + (k < first_move ? 0.0 : v[0][k] - 3.0);
  }
  return v;
}

TEST(AutoBaseline, ASteadyWindowOfTauHighBeforeTheFirstMoveIsTheBaseline) {
  const AutoBaseline b = auto_baseline(mv_cv(500, 60, 0.0), 1, 1.0, 50.0);
  EXPECT_TRUE(b.at_rest);
  EXPECT_EQ(b.steady_rows, 60U);
  EXPECT_EQ(b.note, "steady window 0 … 60 min before the first MV move");
}

TEST(AutoBaseline, MvsMovingBeforeTauHighOrACvDriftingMeanTheStartIsNotAtRest) {
  const AutoBaseline early = auto_baseline(mv_cv(500, 20, 0.0), 1, 1.0, 50.0);
  EXPECT_FALSE(early.at_rest);
  EXPECT_NE(early.note.find("the MVs move 20 min after the start, before a steady window of 50"),
            std::string::npos)
      << early.note;
  const AutoBaseline drifting = auto_baseline(mv_cv(500, 60, 0.02), 1, 1.0, 50.0);
  EXPECT_FALSE(drifting.at_rest);
  EXPECT_NE(drifting.note.find("CV 1 drifts"), std::string::npos) << drifting.note;
}

TEST(ImportRun, AutoBaselineOfAMidTestStartIsTheRecordsMeanAndTheLogSaysSo) {
  ImportOptions o = two_tags();
  o.baseline_auto = true;
  const ImportedRun r = import_historian(ramp_data(100), o);  // a square wave from row 0
  EXPECT_FALSE(r.start_at_rest);
  EXPECT_DOUBLE_EQ(r.input_baseline[0], 3.5);  // the square wave's mean, not its first 3
  const std::string text = run_log_text(r, "h.csv");
  EXPECT_NE(text.find("\n# start_at_rest: no\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n# baseline: start not at rest ("), std::string::npos) << text;
}

}  // namespace
}  // namespace excite::host::historian
