// SPDX-License-Identifier: MIT
// The model file keeps a gain's projected 95 % interval (host/identify/gain_profile.hpp,
// project_gains_near_zero): written with the interval it widens ("K_interval95"), read back,
// and refused by name when it does not hold the gain.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "host/export/model_file.hpp"

namespace excite::host {
namespace {

// One first-order element y1 <- u1 with K = −0.02 ± 0.01 and a projected [−0.1, 0.05].
IdentificationResult small_gain_model() {
  IdentificationResult r;
  r.model.inputs = 1;
  r.model.outputs = 1;
  r.model.sample_time_min = 1.0;
  ElementEstimate e;
  e.value = with_structure(ElementModel{-0.02, 5.0, 30.0, 0.0}, Structure::first_order);
  e.std_error = with_structure(ElementModel{0.01, 1.0, 4.0, 0.0}, Structure::first_order);
  e.projected_gain = ProjectedGain{{-0.1, 0.05}, "projected from its joint 95 % region"};
  r.model.elements = {e};
  r.fits.resize(1);
  return r;
}

std::filesystem::path written(const nlohmann::json& j, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path) << j.dump(1);
  return path;
}

TEST(ModelFile, AProjectedGainIntervalTravelsThroughTheFileAndABadOneIsRefusedByName) {
  const nlohmann::json j = model_json(small_gain_model(), {"u1"}, {"y1"});
  const nlohmann::json& element = j["outputs"][0]["elements"][0];
  ASSERT_TRUE(element.contains("K_projected")) << element;
  EXPECT_EQ(element["K_interval95"], nlohmann::json::array({-0.1, 0.05}));
  const IdentifiedModel read = read_model_file(written(j, "projected.json"));
  const ElementEstimate& e = read.element(0, 0);
  ASSERT_TRUE(e.projected_gain);
  EXPECT_EQ(e.projected_gain->bounds.lower, -0.1);
  EXPECT_EQ(e.projected_gain->bounds.upper, 0.05);
  EXPECT_EQ(e.projected_gain->why, "projected from its joint 95 % region");
  EXPECT_EQ(gain_interval_95(e).lower, -0.1);

  // Without a projection the reported interval is K ± 1.96·SE, and no K_projected is written.
  IdentificationResult plain = small_gain_model();
  plain.model.elements[0].projected_gain.reset();
  const nlohmann::json p = model_json(plain, {"u1"}, {"y1"});
  EXPECT_FALSE(p["outputs"][0]["elements"][0].contains("K_projected"));
  EXPECT_NEAR(p["outputs"][0]["elements"][0]["K_interval95"][0].get<double>(), -0.02 - 0.0196,
              1e-12);

  nlohmann::json bad = j;
  bad["outputs"][0]["elements"][0]["K_projected"]["lower"] = 0.0;  // above K
  try {
    read_model_file(written(bad, "bad.json"));
    ADD_FAILURE() << "a projected interval that misses K was read";
  } catch (const std::invalid_argument& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("K_projected"), std::string::npos) << what;
    EXPECT_NE(what.find("lower <= K <= upper"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace excite::host
