// SPDX-License-Identifier: MIT
// The chapter-6 campaign on the Wood–Berry column (small: 945-sample experiments): every
// design identified and cross-validated, and the summary and report written.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "host/campaign/campaign.hpp"
#include "host/campaign/report.hpp"

namespace excite::host {
namespace {

class WoodBerryCampaign : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    CampaignOptions options;
    options.plant = "woodberry2x2";
    result_ = new CampaignResult(run_campaign(options, {}));
  }
  static void TearDownTestSuite() { delete result_; }
  static CampaignResult* result_;
};
CampaignResult* WoodBerryCampaign::result_ = nullptr;

TEST_F(WoodBerryCampaign, IdentifiesEveryDesignOfTable61) {
  ASSERT_EQ(result_->experiments.size(), 17U);
  for (const Experiment& e : result_->experiments) {
    EXPECT_GT(e.fit_avg, 0.0) << e.name;
    EXPECT_LE(e.crossfit_worst, e.crossfit_avg) << e.name;
    EXPECT_LE(e.crossfit_avg, e.crossfit_best) << e.name;
    EXPECT_GE(e.ratio, 0.0) << e.name;
    EXPECT_LE(e.ratio, 1.0) << e.name;
  }
}

TEST_F(WoodBerryCampaign, StepTestEstimatesTheGainThatTheDirectionalDesignsUse) {
  EXPECT_EQ(result_->design_gain_source, "step test (stepSeq)");
  // Noise 0.03 on outputs of size ~10: G(0) within 10 % of the true one.
  const Eigen::MatrixXd error = result_->design_gain.gain - result_->true_gain.gain;
  EXPECT_LT(error.norm() / result_->true_gain.gain.norm(), 0.1);
}

TEST_F(WoodBerryCampaign, WritesTheSummaryAndTheReportWithFigures) {
  const auto dir = std::filesystem::temp_directory_path() / "excite_campaign_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_summary(*result_, dir);
  write_report(*result_, *sim::make_plant("woodberry2x2"), dir);
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  ASSERT_EQ(summary["experiments"].size(), 17U);
  for (const char* key :
       {"name", "cf_avg", "pips_avg", "fit_avg", "crossfit_avg", "crossfit_best", "crossfit_worst",
        "singular_values", "projection_std", "ratio", "upsilon"}) {
    EXPECT_TRUE(summary["experiments"][0].contains(key)) << key;
  }
  EXPECT_TRUE(std::filesystem::file_size(dir / "index.html") > 1000);
  for (const char* figure : {"sigma.svg", "projections.svg", "prbsUnc.svg", "msGlmZipm.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "figures" / figure)) << figure;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace excite::host
