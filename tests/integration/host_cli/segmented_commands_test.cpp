// SPDX-License-Identifier: MIT
// validate, balance and crossval on a run log with a plant restart in it (issue 23 §4): they used
// to refuse a row flagged discontinuity; they now work per segment by identify's rule
// (host/identify/run_log_input.hpp). The log here is two runs of the same plan joined, the second
// one's first row flagged discontinuity: per segment they must say what each run alone says.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_process.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
  return fields;
}

class SegmentedCommands : public ExciteCli {
 protected:
  // a.csv and b.csv: the plan on woodberry2x2 with two noise seeds; joined.csv: a then b,
  // b's rows numbered on, its first row flagged discontinuity (64); model.json from a.
  void SetUp() override {
    ExciteCli::SetUp();
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("p.plan")).exit_code,
        0);
    for (const char* run : {"a", "b"}) {
      ASSERT_EQ(
          excite("simulate " + path("p.plan") + " --plant woodberry2x2 --noise-var 5e-4 --seed " +
                 (run[0] == 'a' ? "1" : "2") + " -o " + path((std::string(run) + ".csv").c_str()))
              .exit_code,
          0);
    }
    ASSERT_EQ(excite("identify " + path("a.csv") + " -o " + path("model.json")).exit_code, 0);
    const std::vector<std::string> a = lines_of(bytes_of(path("a.csv")));
    const std::vector<std::string> b = lines_of(bytes_of(path("b.csv")));
    std::ofstream out(path("joined.csv"));
    std::size_t rows_a = 0;
    for (const std::string& line : a) {
      out << line << '\n';
      if (!line.empty() && line[0] != '#' && line.rfind("t_min", 0) != 0) ++rows_a;
    }
    bool first = true;
    for (const std::string& line : b) {
      if (line.empty() || line[0] == '#' || line.rfind("t_min", 0) == 0) continue;
      std::vector<std::string> f = fields_of(line);
      const auto k = std::stoul(f[1]) + rows_a;
      f[0] = std::to_string(k);  // T = 1 min
      f[1] = std::to_string(k);
      if (first) f[f.size() - 3] = "64";  // flags (v3: …,flags,state,segment): a restart
      first = false;
      for (std::size_t i = 0; i < f.size(); ++i) out << (i ? "," : "") << f[i];
      out << '\n';
    }
    rows_a_ = static_cast<long>(rows_a);
  }
  nlohmann::json json_of(const std::string& args) {
    const Result r = excite(args + " --json");
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.out;
    const std::string text = r.out.substr(r.out.find('{'));
    return nlohmann::json::parse(text);
  }
  long rows_a_ = 0;
};

TEST_F(SegmentedCommands, ValidateScoresEachSegmentFromRestAsEachRunAlone) {
  const nlohmann::json joined =
      json_of("validate " + path("model.json") + " " + path("joined.csv"));
  const nlohmann::json a = json_of("validate " + path("model.json") + " " + path("a.csv"));
  const nlohmann::json b = json_of("validate " + path("model.json") + " " + path("b.csv"));
  ASSERT_EQ(joined["segments"].size(), 2U) << joined.dump(1);
  EXPECT_EQ(joined["data"]["discontinuities"], 1);
  EXPECT_EQ(joined["segments"][0]["first_row"], 1);
  EXPECT_EQ(joined["segments"][1]["first_row"], rows_a_ + 1);
  for (std::size_t o = 0; o < 2; ++o) {
    // The first segment is run a, every row scored: the same fit to rounding.
    EXPECT_NEAR(joined["segments"][0]["fit"][o].get<double>(), a["outputs"][o]["fit"].get<double>(),
                1e-9);
    // The second is run b from rest, less its warm-up (20 rows of 945): within a percent.
    EXPECT_NEAR(joined["segments"][1]["fit"][o].get<double>(), b["outputs"][o]["fit"].get<double>(),
                1.0);
    const double both = joined["outputs"][o]["fit"].get<double>();
    EXPECT_GT(
        both,
        std::min(a["outputs"][o]["fit"].get<double>(), b["outputs"][o]["fit"].get<double>()) - 1.0);
  }
  // The text says it per segment too, and warns with the counts.
  const Result text = excite("validate " + path("model.json") + " " + path("joined.csv"));
  EXPECT_EQ(text.exit_code, 0) << text.out;
  EXPECT_NE(text.out.find("1 discontinuities (plant restart)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("first row"), std::string::npos) << text.out;
}

TEST_F(SegmentedCommands, BalanceMeasuresEachSegmentAboutItsOwnMeanAsEachRunAlone) {
  const nlohmann::json joined = json_of("balance " + path("joined.csv") + " --plant woodberry2x2");
  const nlohmann::json a = json_of("balance " + path("a.csv") + " --plant woodberry2x2");
  ASSERT_EQ(joined["segments"].size(), 2U) << joined.dump(1);
  EXPECT_NEAR(joined["segments"][0]["ratio"].get<double>(), a["ratio"].get<double>(), 1e-12);
  EXPECT_NEAR(joined["segments"][0]["upsilon"].get<double>(), a["upsilon"].get<double>(), 1e-12);
  EXPECT_GT(joined["ratio"].get<double>(), 0.0);
  EXPECT_LE(joined["ratio"].get<double>(), 1.0);
  // An unflagged log is one segment and gives what balance always gave.
  EXPECT_EQ(a["segments"].size(), 1U);
}

// crossval takes the joined log too (it refused it), and scores a model on it exactly as
// validate does: the model of run a on the joined log is validate's average fit.
TEST_F(SegmentedCommands, CrossvalScoresTheJoinedLogAsValidateDoes) {
  const nlohmann::json cv = json_of("crossval " + path("a.csv") + " " + path("joined.csv"));
  const nlohmann::json on_a = json_of("validate " + path("model.json") + " " + path("a.csv"));
  const nlohmann::json on_joined =
      json_of("validate " + path("model.json") + " " + path("joined.csv"));
  const auto average = [](const nlohmann::json& v) {
    return 0.5 * (v["outputs"][0]["fit"].get<double>() + v["outputs"][1]["fit"].get<double>());
  };
  ASSERT_EQ(cv["fit"].size(), 2U) << cv.dump(1);
  EXPECT_NEAR(cv["fit"][0][0].get<double>(), average(on_a), 1e-6);
  EXPECT_NEAR(cv["fit"][0][1].get<double>(), average(on_joined), 1e-6);
  EXPECT_GT(cv["fit"][1][1].get<double>(), 80.0);  // the joined log's own model
}

}  // namespace
