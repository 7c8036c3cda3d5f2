// SPDX-License-Identifier: MIT
// The controller file (sim/control/controller_file.hpp, make_controller.hpp): what the
// writer writes the reader reads back; every kind of bad value is refused by name in the
// one form "FILE:LINE:COL: FIELD = VALUE, expected WHAT"; a DMC whose model is not
// integrally controllable for the plant is refused, saying so. Real files in a temporary
// folder.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "base/config/error.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/library/library.hpp"

namespace excite::sim::control {
namespace {

using ::testing::HasSubstr;

constexpr const char* kDmcFile = R"(kind = "dmc"
sample_time_min = 1.0

[model]
plant = "woodberry2x2"
delay_samples = 1

[dmc]
prediction_horizon = 60
control_horizon = 4
slack_weight = 1000.0

[[mv]]
min = -0.5
max = 0.5
max_move = 0.1
move_suppression = 0.2

[[mv]]
move_suppression = 0.3

[[cv]]
weight = 2.0
limits = [-1.5, 1.5]

[[cv]]
weight = 0.0
zone = [-0.25, 0.25]
)";

constexpr const char* kPiFile = R"(kind = "pi"
sample_time_min = 1.0
[model]
plant = "woodberry2x2"
[[mv]]
min = -0.3
max = 0.3
[[mv]]
[[pairing]]
cv = 1
mv = 1
kc = 0.375
ti_min = 8.29
[[pairing]]
cv = 2
mv = 2
kc = -0.075
ti_min = 23.6
)";

// The message of reading `text` as "c.toml", or "(accepted)".
std::string refusal(const std::string& text) {
  try {
    controller_from_toml(text, "c.toml");
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

// `key = value` replaced in kDmcFile (the first line that starts with `key`).
std::string dmc_with(const std::string& key, const std::string& line) {
  std::string text = kDmcFile;
  const std::size_t at = text.find("\n" + key) + 1;
  const std::size_t end = text.find('\n', at);
  return text.replace(at, end - at, line);
}

TEST(ControllerFile, ReadsADmcFile) {
  const ControllerFile f = controller_from_toml(kDmcFile, "c.toml");
  EXPECT_EQ(f.kind, ControllerKind::dmc);
  EXPECT_EQ(f.model.plant, "woodberry2x2");
  EXPECT_EQ(f.model.delay_samples, 1);
  EXPECT_EQ(f.dmc.prediction_horizon, 60);
  EXPECT_EQ(f.dmc.control_horizon, 4);
  ASSERT_EQ(f.dmc.mv.size(), 2U);
  EXPECT_EQ(f.dmc.mv[0].max_move, 0.1);
  EXPECT_EQ(f.dmc.mv[1].min, -kUnlimited);
  ASSERT_EQ(f.dmc.cv.size(), 2U);
  EXPECT_EQ(f.dmc.cv[0].limit_high, 1.5);
  EXPECT_TRUE(f.dmc.cv[1].zone);
  EXPECT_EQ(f.dmc.cv[1].zone_low, -0.25);
}

TEST(ControllerFile, WhatTheWriterWritesTheReaderReadsBack) {
  for (const char* text : {kDmcFile, kPiFile}) {
    const ControllerFile f = controller_from_toml(text, "c.toml");
    const std::string written = controller_file_toml(f);
    const ControllerFile again = controller_from_toml(written, "written.toml");
    EXPECT_EQ(controller_file_toml(again), written);
    EXPECT_EQ(again.kind, f.kind);
    EXPECT_EQ(again.dmc.mv.size(), f.dmc.mv.size());
    EXPECT_EQ(again.dmc.cv.size(), f.dmc.cv.size());
    EXPECT_EQ(again.pairing.size(), f.pairing.size());
    if (!f.pairing.empty()) {
      EXPECT_EQ(again.pairing[1].gain, -0.075);
    }
    if (!f.dmc.cv.empty()) {
      EXPECT_EQ(again.dmc.cv[1].zone_high, 0.25);
    }
  }
}

TEST(ControllerFile, RefusesBadValuesByName) {
  EXPECT_EQ(refusal(dmc_with("kind", "kind = \"mpc\"")),
            "c.toml:1:8: kind = \"mpc\", expected \"dmc\" or \"pi\"");
  EXPECT_THAT(refusal(dmc_with("sample_time_min", "sample_time_min = 0")),
              HasSubstr("c.toml:2:19: sample_time_min = 0, expected"));
  EXPECT_THAT(refusal(dmc_with("control_horizon", "control_horizon = 61")),
              HasSubstr("dmc.control_horizon = 61, expected an integer 1..60 (at most "
                        "prediction_horizon)"));
  EXPECT_THAT(refusal(dmc_with("prediction_horizon", "prediction_horizon = 2.5")),
              HasSubstr("dmc.prediction_horizon = 2.5, expected"));
  EXPECT_THAT(refusal(dmc_with("min", "min = 0.7")),
              HasSubstr("mv[0].max = 0.5, expected a number above min (0.7)"));
  EXPECT_THAT(refusal(dmc_with("max_move", "max_move = -1")),
              HasSubstr("c.toml:16:12: mv[0].max_move = -1, expected > 0"));
  EXPECT_THAT(refusal(dmc_with("zone", "zone = [0.1, 0.25]")),
              HasSubstr("cv[1].zone = [0.1, 0.25], expected [low, high] about the setpoint with "
                        "low <= 0 <= high, low < high"));
  EXPECT_THAT(refusal(dmc_with("limits", "limits = [1.5, -1.5]")),
              HasSubstr("cv[0].limits = [1.5, -1.5], expected [low, high] with low < high"));
  EXPECT_THAT(refusal(dmc_with("weight", "weight = -2.0")),
              HasSubstr("cv[0].weight = -2.0, expected"));
  EXPECT_THAT(refusal(dmc_with("slack_weight", "slack_weigth = 1000.0")),
              HasSubstr("dmc.slack_weigth = 1000.0 (unknown key), expected one of the known keys"));
  EXPECT_THAT(
      refusal(dmc_with("plant", "plant = \"woodberry2x2\"\nmodel_file = \"m.json\"")),
      HasSubstr("model.model_file = \"m.json\", expected either plant or model_file, not both"));
  EXPECT_THAT(refusal(dmc_with("plant", "probe_step = 1.0")),
              HasSubstr("model.plant = (missing), expected a plant name, a plant file (.toml) or "
                        "model_file = MODEL.json"));
  // A PI file takes no [dmc], [[cv]] or move suppression, and needs its pairings.
  std::string pi = kPiFile;
  EXPECT_THAT(refusal(pi + "[dmc]\nprediction_horizon = 3\n"),
              HasSubstr("dmc = (a table) (unknown key)"));
  EXPECT_THAT(refusal(std::string(kPiFile).replace(pi.find("kc = 0.375"), 10, "kc = 0")),
              HasSubstr("pairing[0].kc = 0, expected a gain other than 0"));
  EXPECT_THAT(refusal(std::string(kPiFile).replace(pi.find("ti_min = 8.29"), 13, "ti_min = -1")),
              HasSubstr("pairing[0].ti_min = -1, expected"));
  EXPECT_THAT(refusal(std::string(kPiFile).replace(pi.find("cv = 1"), 6, "cv = 0")),
              HasSubstr("pairing[0].cv = 0, expected a CV number 1.. (1-based)"));
  EXPECT_THAT(refusal(std::string(kPiFile).replace(pi.find("max = 0.3"), 9,
                                                   "max = 0.3\nmove_suppression = 1.0")),
              HasSubstr("mv[0].move_suppression = 1.0 (unknown key)"));
  EXPECT_THAT(refusal(pi.substr(0, pi.find("[[pairing]]"))),
              HasSubstr("pairing = (missing), expected one [[pairing]] per loop"));
}

// make_controller's refusals need the model.
std::string make_refusal(const std::string& text, const Eigen::MatrixXd* plant_gain = nullptr) {
  try {
    const ControllerFile f = controller_from_toml(text, "c.toml");
    auto model = load_model(f);
    make_controller(f, *model, plant_gain);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ControllerFile, RefusesWhatDoesNotFitTheModelByName) {
  std::string pi = kPiFile;
  EXPECT_EQ(make_refusal(kPiFile), "(accepted)");
  EXPECT_EQ(make_refusal(kDmcFile), "(accepted)");
  EXPECT_EQ(make_refusal(std::string(kPiFile).replace(pi.find("cv = 2"), 6, "cv = 3")),
            "c.toml: pairing[1].cv = 3, expected a CV 1..2 of the model");
  EXPECT_EQ(make_refusal(std::string(kPiFile).replace(pi.find("kc = -0.075"), 11, "kc = 0.075")),
            "c.toml: pairing[1].kc = 0.075, expected a gain of the sign of the paired G(0) element "
            "(-19.4): the other sign is positive feedback");
  EXPECT_EQ(make_refusal(std::string(kPiFile).replace(pi.find("[[mv]]\n[[pairing]]"), 7, "")),
            "c.toml: mv = 1 entries, expected 2 (one per input (MV) of the model, in its order)");
  EXPECT_EQ(make_refusal(std::string(kDmcFile) + "\n[[cv]]\nweight = 1.0\n"),
            "c.toml: cv = 3 entries, expected 2 (one per output (CV) of the model, in its order)");
  EXPECT_EQ(make_refusal(dmc_with("plant", "model_file = \"m.json\"")),
            "c.toml: model.model_file = \"m.json\", expected a plant name or plant file here: a "
            "model of excite identify is read by excite (host/export), which passes its plant "
            "to make_controller");
  EXPECT_THAT(make_refusal(dmc_with("plant", "plant = \"nosuchplant\"")), HasSubstr("c.toml: "));
}

// A plant file in a temporary folder, removed at the end.
class TempFolder {
 public:
  TempFolder()
      : path_(std::filesystem::temp_directory_path() /
              ("sim_control_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }

 private:
  std::filesystem::path path_;
};

TEST(ControllerFile, ADmcModelWithAMinorOfTheWrongSignIsRefusedAsNotIntegrallyControllable) {
  // Wood–Berry: det G(0) = 12.8·(−19.4) − (−18.9)·6.6 = −123.58. A model with G12 = −40
  // instead of −18.9 has det = −248.32 + 264 = +15.68: the wrong sign.
  TempFolder folder;
  folder.write("wrong.toml", R"toml(name = "wrong"
G = [["12.8 e^-1s / (16.7s+1)", "-40 e^-3s / (21s+1)"],
     ["6.6 e^-7s / (10.9s+1)", "-19.4 e^-3s / (14.4s+1)"]]
)toml");
  const auto file = folder.write("dmc.toml", dmc_with("plant", "plant = \"wrong.toml\""));
  const ControllerFile f = load_controller_file(file);
  EXPECT_EQ(f.model.plant, (file.parent_path() / "wrong.toml").string());
  auto model = load_model(f);
  const Eigen::MatrixXd plant_gain = library_plant("woodberry2x2").static_gain();
  try {
    make_controller(f, *model, &plant_gain);
    FAIL() << "the model is not integrally controllable for the plant";
  } catch (const config::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": model = \"" + f.model.plant +
                  "\" with det G(0)[1,2] = 15.68 where the plant's is -123.6, expected a model "
                  "whose principal minors of G(0) all have the plant's signs (this one is not "
                  "integrally controllable: under integral action the loop would be unstable)");
  }
  // The plant's own model passes, and without a plant to compare with nothing is checked.
  auto right = make_plant("woodberry2x2");
  EXPECT_NO_THROW(make_controller(f, *right, &plant_gain));
  EXPECT_NO_THROW(make_controller(f, *model, nullptr));
  // A plant of another size cannot be run by this model's controller.
  const Eigen::MatrixXd other = library_plant("alatiqi4x4").static_gain();
  try {
    make_controller(f, *right, &other);
    FAIL() << "a 2×2 model's controller cannot run a 4×4 plant";
  } catch (const config::Error& e) {
    EXPECT_THAT(e.what(), HasSubstr(": model = \"" + f.model.plant +
                                    "\" (2×2), expected the plant's size, 4×4 (outputs × inputs)"));
  }
}

TEST(ControllerFile, AModelThatNeverSettlesIsRefusedForDmc) {
  TempFolder folder;
  folder.write("integrator.toml", R"toml(allow_unstable = true
G = [["0.1/s", "0"], ["0", "1/(10s+1)"]]
)toml");
  const auto file = folder.write("dmc.toml", dmc_with("plant", "plant = \"integrator.toml\""));
  const ControllerFile f = load_controller_file(file);
  auto model = load_model(f);
  try {
    make_controller(f, *model);
    FAIL() << "an integrating model has no truncated step model";
  } catch (const config::Error& e) {
    EXPECT_THAT(e.what(), HasSubstr(file.string() + ": model = "));
    EXPECT_THAT(e.what(), HasSubstr("expected a model whose every step response settles"));
  }
}

}  // namespace
}  // namespace excite::sim::control
