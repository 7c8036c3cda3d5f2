// SPDX-License-Identifier: MIT
// The `excite` executable run as a process, as an engineer or a script would: its output
// formats, exit codes and refusals are a contract (host/README.md).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli_process.hpp"

namespace {

using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

TEST_F(ExciteCli, GainsJsonHasTheContractKeysAndTheSpecSingularValues) {
  const Result r = excite("gains --plant alatiqi4x4 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"gain", "singular_values", "condition_number", "xi", "rga",
                          "input_directions", "output_directions"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_NEAR(j["singular_values"][0].get<double>(), 20.470, 0.0005);
  EXPECT_NEAR(j["singular_values"][3].get<double>(), 0.1635, 0.00005);
  EXPECT_EQ(j["input_directions"].size(), 4U);
}

TEST_F(ExciteCli, DesignThenInspectGivesTheInputTable) {
  const Result d = excite("design --plant alatiqi4x4 --preset prbsUnc -o " + path("unc.plan"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_NE(d.out.find("(4.2.3)"), std::string::npos) << d.out;
  const Result r = excite("inspect " + path("unc.plan") + " --json --plant alatiqi4x4");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["channels"].size(), 4U);
  for (const auto& c : j["channels"]) {
    EXPECT_NEAR(c["cf"].get<double>(), 1.0, 1e-12);  // ±c/|G(0) e_j| PRBS
    // ±1 m-sequence of period 255: mean 1/255, RMS 1, range 2 → PIPS = 100·√(1 − 1/255²)
    EXPECT_NEAR(c["pips"].get<double>(), 100.0 * std::sqrt(1.0 - 1.0 / (255.0 * 255.0)), 1e-10);
  }
  EXPECT_TRUE(j["average"].contains("cf"));
  EXPECT_TRUE(j["average"].contains("pips"));
  EXPECT_EQ(j["static_output_excursions"].size(), 4U);
}

TEST_F(ExciteCli, DesignFromSpecWritesAPlan) {
  std::ofstream(path("spec.toml")) << R"(design = "stepDir"
plant = "woodberry2x2"
[prior]
inputs = 2
sample_time_min = 1.0
tau_low_min = 10.9
tau_high_min = 21.0
alpha = 2.0
beta = 3.0
[[input]]
name = "reflux"
amplitude = 1.0
min = -2.0
max = 2.0
[[input]]
name = "steam"
amplitude = 1.0
min = -2.0
max = 2.0
)";
  const Result d = excite("design " + path("spec.toml") + " -o " + path("wb.plan"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_TRUE(std::filesystem::exists(path("wb.plan")));
}

// Issue 3 §4: a flat spectrum of lines 1…31 on a 256-sample period; Schroeder's closed form
// gives a continuous crest factor of about 1.78, Guillaume's optimisation at most 1.40.
TEST_F(ExciteCli, PlainMultisineSpecReportsTheContinuousCrestFactor) {
  for (const auto& [phases, low, high] :
       {std::tuple{"schroeder", 1.76, 1.80}, std::tuple{"guillaume", 1.30, 1.40}}) {
    std::ofstream(path("ms.toml"))
        << "design = \"multisine\"\n[prior]\ninputs = 1\nsample_time_min = 1.0\n"
           "[[input]]\nname = \"u\"\namplitude = 1.0\nmin = -1.0\nmax = 1.0\n"
           "[multisine]\nperiod = 256\nfirst_line = 1\nlast_line = 31\nphases = \""
        << phases << "\"\n";
    ASSERT_EQ(excite("design -q " + path("ms.toml") + " -o " + path("ms.plan")).exit_code, 0)
        << phases;
    const Result r = excite("inspect --json " + path("ms.plan"));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const double cf = nlohmann::json::parse(r.out)["channels"][0]["cf_continuous"].get<double>();
    EXPECT_GT(cf, low) << phases;
    EXPECT_LT(cf, high) << phases;
  }
}

TEST_F(ExciteCli, InspectGivesNoContinuousCrestFactorForPrbs) {
  ASSERT_EQ(excite("design -q --plant alatiqi4x4 --preset prbsSeq -o " + path("p.plan")).exit_code,
            0);
  const auto j = nlohmann::json::parse(excite("inspect --json " + path("p.plan")).out);
  EXPECT_TRUE(j["channels"][0]["cf_continuous"].is_null());
}

TEST_F(ExciteCli, BadSpecIsRefusedWithFieldAndWritesNothing) {
  std::ofstream(path("bad.toml"))
      << "design = \"prbsUnc\"\n[prior]\ninputs = 1\nsample_time_min = 1.0\n"
         "tau_low_min = -3\ntau_high_min = 50\nalpha = 2\nbeta = 3\n"
         "[[input]]\nname = \"u\"\namplitude = 1\nmin = -1\nmax = 1\n";
  const Result d = excite("design " + path("bad.toml") + " -o " + path("bad.plan"));
  EXPECT_EQ(d.exit_code, 1);
  EXPECT_NE(d.out.find("tau_low_min = -3"), std::string::npos) << d.out;
  EXPECT_FALSE(std::filesystem::exists(path("bad.plan")));
  // Nothing else either (no temporary file): the folder holds the spec alone.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            1);
}

TEST_F(ExciteCli, CorruptedPlanIsRefused) {
  ASSERT_EQ(excite("design --plant alatiqi4x4 --preset stepSeq -q -o " + path("s.plan")).exit_code,
            0);
  {
    std::fstream f(path("s.plan"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(40);
    f.put('\x5a');
  }
  const Result r = excite("inspect " + path("s.plan"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(path("s.plan")), std::string::npos) << r.out;
}

// The host's hop: design → simulate → run log → identify → validate, balance.
TEST_F(ExciteCli, SimulatedRunIsIdentifiedValidatedAndBalanced) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  const Result sim = excite("simulate " + path("wb.plan") +
                            " --plant woodberry2x2 --noise-var 5e-4 --seed 7 -o " + path("wb.csv"));
  ASSERT_EQ(sim.exit_code, 0) << sim.out;
  const Result id = excite("identify --json -o " + path("wb.json") + " " + path("wb.csv"));
  ASSERT_EQ(id.exit_code, 0) << id.out;
  const auto model = nlohmann::json::parse(id.out);
  for (const char* key : {"outputs", "gain", "singular_values", "condition_number"})
    EXPECT_TRUE(model.contains(key)) << key;
  EXPECT_GT(model["outputs"][0]["fit"].get<double>(), 90.0);
  // Wood–Berry G(0) = [12.8 −18.9; 6.6 −19.4]: the noisy PRBS run (sized to static outputs
  // of norm 1, the case study's noise 5e-4, SPEC §3–§4) recovers it closely.
  EXPECT_NEAR(model["gain"][0][0].get<double>(), 12.8, 0.5);
  EXPECT_NEAR(model["gain"][1][1].get<double>(), -19.4, 0.5);
  const Result v = excite("validate --json " + path("wb.json") + " " + path("wb.csv"));
  ASSERT_EQ(v.exit_code, 0) << v.out;
  EXPECT_NEAR(nlohmann::json::parse(v.out)["outputs"][0]["fit"].get<double>(),
              model["outputs"][0]["fit"].get<double>(), 1e-9);
  const Result b = excite("balance --json --plant woodberry2x2 " + path("wb.csv"));
  ASSERT_EQ(b.exit_code, 0) << b.out;
  const auto balance = nlohmann::json::parse(b.out);
  EXPECT_EQ(balance["projection_std"].size(), 2U);
  EXPECT_GT(balance["ratio"].get<double>(), 0.0);
  EXPECT_GT(balance["upsilon"].get<double>(), 0.0);
}

// The time constants' upper bound (SPEC §6): β·τ_H of the design the run log carries in its
// header (woodberry2x2: 3 × 21 = 63 min), --max-time-constant or --tau-high to override; the
// text output says which. A bound below the plant's 21-min lag shows in the estimates.
TEST_F(ExciteCli, IdentifyBoundsTheTimeConstantsByBetaTauHigh) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  ASSERT_EQ(excite("simulate " + path("wb.plan") + " --plant woodberry2x2 -o " + path("wb.csv"))
                .exit_code,
            0);
  const Result def = excite("identify " + path("wb.csv"));
  ASSERT_EQ(def.exit_code, 0) << def.out;
  EXPECT_NE(def.out.find("time constants bounded by 63 min (beta x tau_H of the run log " +
                         path("wb.csv") + ", beta = 3, tau_H = 21 min)"),
            std::string::npos)
      << def.out;
  EXPECT_NE(excite("identify --tau-high 10 --beta 2 " + path("wb.csv"))
                .out.find("bounded by 20 min (beta 2 x --tau-high)"),
            std::string::npos);
  const Result low = excite("identify --json --max-time-constant 15 " + path("wb.csv"));
  ASSERT_EQ(low.exit_code, 0) << low.out;
  const nlohmann::json model = nlohmann::json::parse(low.out);  // outlives the loop (C++20)
  int on_upper_bound = 0;  // a parameter ending on a bound is listed, per element
  for (const auto& out : model["outputs"]) {
    for (const auto& e : out["elements"]) {
      EXPECT_LE(e["Tp1"].get<double>(), 15.0) << e;
      const auto listed = e["on_bound"].get<std::vector<std::string>>();
      const bool tp1_listed =
          std::find(listed.begin(), listed.end(), "Tp1 = 15 (upper bound)") != listed.end();
      EXPECT_EQ(tp1_listed, e["Tp1"].get<double>() == 15.0) << e;
      on_upper_bound += tp1_listed ? 1 : 0;
    }
  }
  EXPECT_GT(on_upper_bound, 0);  // the plant's 21-min lags cannot fit under 15 min
  EXPECT_NE(excite("identify --max-time-constant 15 " + path("wb.csv"))
                .out.find("; Tp1 = 15 (upper bound)"),
            std::string::npos);
  const Result bad = excite("identify --max-time-constant -1 " + path("wb.csv"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("--max-time-constant"), std::string::npos) << bad.out;
}

// A run log that carries no time scales (written before they existed, or by hand) from a
// plant with no case study: identify refuses rather than bound the time constants by the
// run's length, and names the ways out; each of them works.
TEST_F(ExciteCli, IdentifyRefusesWhenNoTimeConstantBoundIsKnownAndNamesTheOptions) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  ASSERT_EQ(excite("simulate " + path("wb.plan") + " --plant woodberry2x2 -o " + path("wb.csv"))
                .exit_code,
            0);
  std::ifstream in(path("wb.csv"));
  std::ofstream out(path("unit7.csv"));
  int dropped = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# tau_high_min:", 0) == 0 || line.rfind("# beta:", 0) == 0 ||
        line.rfind("# switch_time_min:", 0) == 0) {
      ++dropped;
      continue;
    }
    out << (line.rfind("# plant:", 0) == 0 ? "# plant: unit 7 column" : line) << '\n';
  }
  out.close();
  ASSERT_EQ(dropped, 3);  // the simulated log carried τ_H, β and T_sw from the plan

  const Result refused = excite("identify " + path("unit7.csv"));
  EXPECT_NE(refused.exit_code, 0) << refused.out;
  for (const char* named : {"tau_high_min", "unit 7 column", "--tau-high", "--max-time-constant",
                            "--max-time-constant 0"}) {
    EXPECT_NE(refused.out.find(named), std::string::npos) << named << " in " << refused.out;
  }
  const Result length = excite("identify --max-time-constant 0 " + path("unit7.csv"));
  ASSERT_EQ(length.exit_code, 0) << length.out;
  EXPECT_NE(length.out.find("(the run's length, --max-time-constant 0)"), std::string::npos)
      << length.out;
  const Result tau = excite("identify --tau-high 21 " + path("unit7.csv"));
  ASSERT_EQ(tau.exit_code, 0) << tau.out;
  EXPECT_NE(tau.out.find("bounded by 63 min (beta 3 x --tau-high)"), std::string::npos) << tau.out;
}

// crossval takes the same bound: noise-free Wood–Berry runs are fitted exactly under the
// default β·τ_H = 63 min, not when the bound (15 min) is below the plant's 21-min lag.
TEST_F(ExciteCli, CrossvalBoundsTheTimeConstantsToo) {
  for (const char* preset : {"prbsUnc", "stepSeq"}) {
    const std::string plan = path((std::string(preset) + ".plan").c_str());
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset " + std::string(preset) + " -o " + plan)
            .exit_code,
        0);
    ASSERT_EQ(excite("simulate " + plan + " --plant woodberry2x2 -o " +
                     path((std::string(preset) + ".csv").c_str()))
                  .exit_code,
              0);
  }
  const std::string runs = path("prbsUnc.csv") + " " + path("stepSeq.csv");
  const Result def = excite("crossval --json " + runs);
  ASSERT_EQ(def.exit_code, 0) << def.out;
  const Result low = excite("crossval --json --max-time-constant 15 " + runs);
  ASSERT_EQ(low.exit_code, 0) << low.out;
  // (the output also carries crossval's "identified RUN" progress lines before the JSON)
  const auto models = [](const std::string& out) {
    return nlohmann::json::parse(out.substr(out.find('{')))["models"];
  };
  for (std::size_t a = 0; a < 2; ++a) {
    EXPECT_GT(models(def.out)[a]["fit_own"].get<double>(), 99.9) << def.out;
    EXPECT_LT(models(low.out)[a]["fit_own"].get<double>(), 99.9) << low.out;
  }
}

TEST_F(ExciteCli, SimulationIsReproducibleBySeed) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset stepSeq -o " + path("s.plan")).exit_code, 0);
  for (const char* name : {"a.csv", "b.csv"}) {
    ASSERT_EQ(excite("simulate " + path("s.plan") +
                     " --plant woodberry2x2 --noise-var 0.03 --seed 3 -o " + path(name))
                  .exit_code,
              0);
  }
  std::ifstream a(path("a.csv")), b(path("b.csv"));
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
            std::string(std::istreambuf_iterator<char>(b), {}));
}

TEST_F(ExciteCli, PlanForAnotherPlantIsRefusedAndNothingWritten) {
  ASSERT_EQ(excite("design -q --plant alatiqi4x4 --preset stepSeq -o " + path("a.plan")).exit_code,
            0);
  const Result r =
      excite("simulate " + path("a.plan") + " --plant woodberry2x2 -o " + path("x.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("4 channels"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("x.csv")));
}

TEST_F(ExciteCli, StepResponseOfTheColumnSettlesTowardsItsGain) {
  const Result r =
      excite("simulate --plant colaA --step L=0.001 --samples 50 -o " + path("step.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("dxD"), std::string::npos) << r.out;
  EXPECT_EQ(excite("identify " + path("nosuch.csv")).exit_code, 1);
}

TEST_F(ExciteCli, UnknownPlantListsTheKnownOnes) {
  const Result r = excite("gains --plant nosuch");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("alatiqi4x4"), std::string::npos) << r.out;
}

TEST_F(ExciteCli, MissingRequiredOptionIsAUsageError) {
  EXPECT_EQ(excite("design --plant alatiqi4x4 --preset stepSeq").exit_code, 2);
}

TEST_F(ExciteCli, EveryCommandHasHelp) {
  for (const char* cmd : {"gains", "design", "inspect", "case-study", "simulate", "identify",
                          "validate", "crossval", "balance", "campaign"}) {
    const Result r = excite(std::string(cmd) + " --help");
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << cmd << ": " << r.out;
  }
}

TEST_F(ExciteCli, CaseStudyPrintsAllSeventeenDesigns) {
  const Result r = excite("case-study --plant alatiqi4x4 -o " + path("plans"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  for (const char* name :
       {"stepSeq", "stepDir", "prbsSeq", "prbsUnc", "prbsSeqDir", "prbsSimDir", "prbsDirCorrSeq",
        "prbsDirCorrSim", "msSrdSeq", "msSrdSeqDir", "msGlmSeq", "msGlmSeqDir", "msSrdSim",
        "msSrdSimDir", "msGlmSim", "msGlmSimDir", "msGlmZipm"}) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
    EXPECT_TRUE(std::filesystem::exists(dir_ / "plans" / (std::string(name) + ".plan"))) << name;
  }
}

// Issue 14: inspect shows every design's per-input min and max side by side.
TEST_F(ExciteCli, InspectOfSeveralPlansShowsEveryDesignsPerInputRange) {
  for (const char* preset : {"prbsUnc", "prbsSimDir"}) {
    ASSERT_EQ(excite(std::string("design -q --plant alatiqi4x4 --preset ") + preset + " -o " +
                     path((std::string(preset) + ".plan").c_str()))
                  .exit_code,
              0);
  }
  const Result r = excite("inspect " + path("prbsUnc.plan") + " " + path("prbsSimDir.plan"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto at = r.out.find("per-input min and max of every design");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string summary = r.out.substr(at);
  for (const char* text : {"u1 min", "u4 max", "prbsUnc", "prbsSimDir"})
    EXPECT_NE(summary.find(text), std::string::npos) << text << "\n" << summary;
}

// A design that does not fit its limits is scaled as a whole and the command says so.
TEST_F(ExciteCli, DesignScaledToItsLimitsSaysByHowMuch) {
  std::ofstream(path("tight.toml")) << R"(design = "prbsSimDir"
plant = "woodberry2x2"
[prior]
inputs = 2
sample_time_min = 1.0
tau_low_min = 10.9
tau_high_min = 21.0
alpha = 2.0
beta = 3.0
[[input]]
name = "reflux"
min = -0.01
max = 0.01
[[input]]
name = "steam"
min = -0.01
max = 0.01
)";
  const Result d = excite("design -q " + path("tight.toml") + " -o " + path("tight.plan"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_NE(d.out.find("whole design is scaled by"), std::string::npos) << d.out;
}

}  // namespace

namespace {

// The dy_* columns of a run log (firmware/runlog/README.md), row by row.
std::vector<std::vector<double>> output_columns(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::vector<std::size_t> dy;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream split(line);
    for (std::string f; std::getline(split, f, ',');) fields.push_back(f);
    if (dy.empty()) {
      for (std::size_t c = 0; c < fields.size(); ++c) {
        if (fields[c].rfind("dy_", 0) == 0) dy.push_back(c);
      }
      continue;
    }
    std::vector<double> row;
    for (const std::size_t c : dy) row.push_back(std::stod(fields.at(c)));
    rows.push_back(row);
  }
  return rows;
}

// An excite model v1 file of the Wood–Berry column's own elements (all first order with a
// delay: exactly of form (6.1.1)).
void write_woodberry_model(const std::string& path) {
  const auto element = [](const char* input, double K, double Td, double Tp1) {
    return nlohmann::json{
        {"input", input},        {"K", K}, {"Td", Td}, {"Tp1", Tp1}, {"Tp2", 0.0}, {"se", nullptr},
        {"status", "identified"}};
  };
  const nlohmann::json model = {
      {"format", "excite model v1"},
      {"sample_time_min", 1.0},
      {"inputs", {"u1", "u2"}},
      {"outputs",
       {{{"name", "y1"},
         {"elements", {element("u1", 12.8, 1.0, 16.7), element("u2", -18.9, 3.0, 21.0)}}},
        {{"name", "y2"},
         {"elements", {element("u1", 6.6, 7.0, 10.9), element("u2", -19.4, 3.0, 14.4)}}}}}};
  std::ofstream(path) << model.dump(2);
}

}  // namespace

// simulate --plant MODEL.json: a model of the plant's own elements gives the plant's run.
TEST_F(ExciteCli, SimulateWithAModelFileReproducesThePlantTheModelEquals) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  write_woodberry_model(path("wb-model.json"));
  const Result plant =
      excite("simulate " + path("wb.plan") + " --plant woodberry2x2 -o " + path("plant.csv"));
  ASSERT_EQ(plant.exit_code, 0) << plant.out;
  const Result model = excite("simulate " + path("wb.plan") + " --plant " + path("wb-model.json") +
                              " -o " + path("model.csv"));
  ASSERT_EQ(model.exit_code, 0) << model.out;
  const auto expected = output_columns(path("plant.csv"));
  const auto got = output_columns(path("model.csv"));
  ASSERT_EQ(got.size(), expected.size());
  ASSERT_GT(got.size(), 900U);
  double largest = 0.0, error = 0.0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    ASSERT_EQ(got[k].size(), 2U);
    for (std::size_t o = 0; o < 2; ++o) {
      largest = std::max(largest, std::abs(expected[k][o]));
      error = std::max(error, std::abs(got[k][o] - expected[k][o]));
    }
  }
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(error, 1e-9 * largest);
  // A model with an element the data did not identify cannot stand in for a plant.
  auto broken = nlohmann::json::parse(std::ifstream(path("wb-model.json")));
  broken["outputs"][1]["elements"][0]["K"] = nullptr;
  broken["outputs"][1]["elements"][0]["reason"] = "u1 not moved";
  std::ofstream(path("broken.json")) << broken.dump();
  const Result refused = excite("simulate " + path("wb.plan") + " --plant " + path("broken.json") +
                                " -o " + path("never.csv"));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.out.find("outputs[1].elements[0] (y2 <- u1)"), std::string::npos)
      << refused.out;
  EXPECT_FALSE(std::filesystem::exists(path("never.csv")));
}

// excite export: every format from an identified model file, written whole or not at all.
TEST_F(ExciteCli, ExportWritesEveryFormatOfAnIdentifiedModel) {
  write_woodberry_model(path("wb-model.json"));
  const Result csv = excite("export " + path("wb-model.json") +
                            " --format step-csv --horizon 60 -o " + path("steps.csv"));
  ASSERT_EQ(csv.exit_code, 0) << csv.out;
  std::ifstream in(path("steps.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 66U);
  EXPECT_EQ(lines[3], "# horizon: 60 samples (60 min)");
  EXPECT_EQ(lines[5], "k,t_min,y1 <- u1,y1 <- u2,y2 <- u1,y2 <- u2");
  // k = 20: y1 <- u1 = 12.8 (1 − e^{−19/16.7}).
  std::stringstream row(lines[5 + 20]);
  std::vector<double> values;
  for (std::string f; std::getline(row, f, ',');) values.push_back(std::stod(f));
  ASSERT_EQ(values.size(), 6U);
  EXPECT_NEAR(values[2], 12.8 * (1.0 - std::exp(-19.0 / 16.7)), 1e-9);
  EXPECT_NEAR(values[4], 6.6 * (1.0 - std::exp(-13.0 / 10.9)), 1e-9);

  const Result csv_default =
      excite("export " + path("wb-model.json") + " --format step-csv -o " + path("settled.csv"));
  ASSERT_EQ(csv_default.exit_code, 0) << csv_default.out;
  EXPECT_NE(csv_default.out.find("150 samples of 1 min"), std::string::npos)  // 3 + 7·21 = 150 min
      << csv_default.out;

  for (const char* format : {"matlab", "python-control", "json"}) {
    const Result r =
        excite("export " + path("wb-model.json") + " --format " + format + " -o " + path(format));
    ASSERT_EQ(r.exit_code, 0) << format << ": " << r.out;
  }
  std::ifstream m(path("matlab"));
  const std::string matlab((std::istreambuf_iterator<char>(m)), std::istreambuf_iterator<char>());
  EXPECT_NE(matlab.find("input_delay_min = [1 3];"), std::string::npos) << matlab;
  EXPECT_NE(matlab.find("io_delay_min = [0 0; 6 0];"), std::string::npos) << matlab;
  const auto json = nlohmann::json::parse(std::ifstream(path("json")));
  EXPECT_EQ(json["format"], "excite transfer matrix v1");
  EXPECT_EQ(json["elements"][1][1]["den"], nlohmann::json({14.4, 1.0}));

  const Result bad_format =
      excite("export " + path("wb-model.json") + " --format csv -o " + path("x"));
  EXPECT_EQ(bad_format.exit_code, 2) << bad_format.out;
  std::ofstream(path("not-a-model.json")) << "{\"format\":\"excite plan\"}";
  const Result not_a_model =
      excite("export " + path("not-a-model.json") + " --format json -o " + path("y"));
  EXPECT_EQ(not_a_model.exit_code, 1);
  EXPECT_NE(not_a_model.out.find("format, expected \"excite model v2\" or \"excite model v1\""),
            std::string::npos)
      << not_a_model.out;
  EXPECT_FALSE(std::filesystem::exists(path("y")));
}

// Issue 18 §4–5 through the files an engineer hands on: identify picks each element's
// structure (alatiqi4x4's (y4, u2) has a lead, a lag and an oscillating pole pair), the model
// file keeps structure, grade and covariance, and export carries them: the JSON with the
// structure's parameters, standard errors and covariance, the step table with ±2σ columns.
// A new test of the same plant re-identified in an earlier model's structures: each element
// keeps its structure (no search); a model of other channels, or with --structure, is refused.
TEST_F(ExciteCli, StructuresFromAnEarlierModelAreKeptPerElement) {
  ASSERT_EQ(excite("design -q --plant alatiqi4x4 --preset prbsUnc -o " + path("a.plan")).exit_code,
            0);
  for (const char* seed : {"3", "4"}) {
    ASSERT_EQ(excite("simulate " + path("a.plan") + " --plant alatiqi4x4 --noise-var 5e-4 --seed " +
                     seed + " -o " + path(("run" + std::string(seed) + ".csv").c_str()))
                  .exit_code,
              0);
  }
  ASSERT_EQ(excite("identify " + path("run3.csv") + " --threads 2 -o " + path("m.json")).exit_code,
            0);
  const auto earlier = nlohmann::json::parse(std::ifstream(path("m.json")));
  const Result again = excite("identify " + path("run4.csv") +
                              " --threads 2 --json --structures-from " + path("m.json"));
  ASSERT_EQ(again.exit_code, 0) << again.out;
  const auto model = nlohmann::json::parse(again.out.substr(again.out.find('{')));
  std::set<std::string> kinds;
  for (std::size_t j = 0; j < 4; ++j) {
    for (std::size_t i = 0; i < 4; ++i) {
      const auto& e = model["outputs"][j]["elements"][i]["structure"];
      EXPECT_EQ(e, earlier["outputs"][j]["elements"][i]["structure"]) << j << "," << i;
      kinds.insert(e.get<std::string>());
    }
  }
  EXPECT_GE(kinds.size(), 2U) << "the earlier model has more than one structure";
  EXPECT_GT(model["outputs"][3]["fit"].get<double>(), 90.0);

  const Result both = excite("identify " + path("run4.csv") +
                             " --structure two_poles --structures-from " + path("m.json"));
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.out.find("excludes"), std::string::npos) << both.out;
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("w.plan")).exit_code, 0);
  ASSERT_EQ(
      excite("simulate " + path("w.plan") + " --plant woodberry2x2 -o " + path("w.csv")).exit_code,
      0);
  const Result other = excite("identify " + path("w.csv") + " --structures-from " + path("m.json"));
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.out.find("m.json"), std::string::npos) << other.out;
}

TEST_F(ExciteCli, IdentifiedStructuresGradesAndBandsTravelThroughTheModelFileAndExport) {
  ASSERT_EQ(excite("design -q --plant alatiqi4x4 --preset prbsUnc -o " + path("a.plan")).exit_code,
            0);
  ASSERT_EQ(excite("simulate " + path("a.plan") +
                   " --plant alatiqi4x4 --noise-var 5e-4 --seed 3 -o " + path("a.csv"))
                .exit_code,
            0);
  const Result id = excite("identify " + path("a.csv") + " --threads 2 -o " + path("m.json"));
  ASSERT_EQ(id.exit_code, 0) << id.out;
  const auto model = nlohmann::json::parse(std::ifstream(path("m.json")));
  EXPECT_EQ(model["format"], "excite model v2");
  const auto& lead = model["outputs"][3]["elements"][1];  // y4 <- u2
  EXPECT_EQ(lead["structure"], "underdamped_lag_zero") << lead;
  EXPECT_NEAR(lead["K"].get<double>(), 14.0, 0.5) << lead;
  ASSERT_EQ(lead["covariance"].size(), 6U);  // K, Td, Tp1, Tz, Tn, zeta
  EXPECT_GT(lead["covariance"][0][0].get<double>(), 0.0);
  EXPECT_NEAR(std::sqrt(lead["covariance"][0][0].get<double>()), lead["se"]["K"].get<double>(),
              1e-9 * lead["se"]["K"].get<double>());
  EXPECT_NE(id.out.find("underdamped_lag_zero"), std::string::npos) << id.out;
  // Each estimated gain's reported 95 % interval holds K ± 1.96·SE (and a projection where
  // there is one: ClosedLoopCommands.AGainNotToldFromZero…).
  for (const auto& out : model["outputs"]) {
    for (const auto& e : out["elements"]) {
      if (!e.contains("K_interval95")) continue;
      const double K = e["K"].get<double>(), half = 1.96 * e["se"]["K"].get<double>();
      EXPECT_LE(e["K_interval95"][0].get<double>(), K - half * (1.0 - 1e-12)) << e;
      EXPECT_GE(e["K_interval95"][1].get<double>(), K + half * (1.0 - 1e-12)) << e;
    }
  }
  // Forced back to (6.1.1), the row cannot be fitted as well.
  const Result forced =
      excite("identify " + path("a.csv") + " --threads 2 --structure two_poles --json");
  ASSERT_EQ(forced.exit_code, 0) << forced.out;
  const auto two = nlohmann::json::parse(forced.out.substr(forced.out.find('{')));
  EXPECT_LT(two["outputs"][3]["fit"].get<double>() + 1.0, model["outputs"][3]["fit"].get<double>());

  ASSERT_EQ(excite("export " + path("m.json") + " --format json -o " + path("t.json")).exit_code,
            0);
  const auto t = nlohmann::json::parse(std::ifstream(path("t.json")));
  const auto& e = t["elements"][3][1];
  EXPECT_EQ(e["structure"], "underdamped_lag_zero");
  for (const char* key : {"K", "Td", "Tp1", "Tz", "Tn", "zeta", "grade", "se", "covariance"})
    EXPECT_TRUE(e.contains(key)) << key << ": " << e;
  EXPECT_EQ(e["den"].size(), 4U);  // (Tp1 s + 1)(Tn² s² + 2ζTn s + 1)
  EXPECT_EQ(e["num"].size(), 2U);  // K (Tz s + 1)
  EXPECT_EQ(e["covariance"], lead["covariance"]);
  // The table without bands has the same coefficients.
  ASSERT_EQ(excite("export " + path("m.json") + " --format step-csv --horizon 200 -o " +
                   path("plain.csv"))
                .exit_code,
            0);
  const Result banded = excite("export " + path("m.json") +
                               " --format step-csv --horizon 200 --bands -o " + path("bands.csv"));
  ASSERT_EQ(banded.exit_code, 0) << banded.out;
  std::ifstream in(path("bands.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::size_t header = 0;
  while (header < lines.size() && lines[header].rfind("k,", 0) != 0) ++header;
  ASSERT_LT(header, lines.size());
  EXPECT_NE(lines[header].find("y4 <- u2,y4 <- u2 -2s,y4 <- u2 +2s"), std::string::npos)
      << lines[header];
  int widening = 0;
  for (std::size_t k = header + 1; k < lines.size(); ++k) {
    std::stringstream row(lines[k]);
    std::vector<double> v;
    for (std::string f; std::getline(row, f, ',');)
      v.push_back(f.empty() ? std::nan("") : std::stod(f));
    ASSERT_EQ(v.size(), 2U + 16U * 3U) << lines[k];
    for (std::size_t c = 2; c < v.size(); c += 3) {  // s, s − 2σ, s + 2σ
      EXPECT_LE(v[c + 1], v[c]) << lines[k];
      EXPECT_GE(v[c + 2], v[c]) << lines[k];
    }
    const std::size_t y4u2 = 2 + 3 * (3 * 4 + 1);
    widening += v[y4u2 + 2] - v[y4u2 + 1] > 0.0 ? 1 : 0;
  }
  EXPECT_GT(widening, 150);  // known after its delay: a band of positive width
  std::ifstream plain_in(path("plain.csv"));
  std::vector<std::string> plain;
  for (std::string line; std::getline(plain_in, line);) plain.push_back(line);
  const auto numbers = [](const std::string& line) {
    std::vector<std::string> f;
    std::stringstream row(line);
    for (std::string x; std::getline(row, x, ',');) f.push_back(x);
    return f;
  };
  const std::vector<std::string> a = numbers(plain.back());
  const std::vector<std::string> b = numbers(lines.back());
  ASSERT_EQ(a.size(), 2U + 16U);
  for (std::size_t c = 0; c < 16; ++c) EXPECT_EQ(a[2 + c], b[2 + 3 * c]) << c;
}

// The in-process campaign keeps every run log and every model beside its report and links
// them (as the --loop campaign keeps its runs).
TEST_F(ExciteCli, CampaignKeepsEveryRunAndModelAndTheReportLinksThem) {
  const Result r = excite("campaign --plant woodberry2x2 --threads 2 -o " + path("camp"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream html_file(path("camp/index.html"));
  const std::string html((std::istreambuf_iterator<char>(html_file)),
                         std::istreambuf_iterator<char>());
  int runs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(path("camp/runs"))) {
    const std::string folder = entry.path().filename().string();
    const auto run = entry.path() / "run.csv";
    ASSERT_TRUE(std::filesystem::exists(run)) << run;
    EXPECT_GT(output_columns(run.string()).size(), 700U) << run;
    EXPECT_NE(html.find("href='runs/" + folder + "/run.csv'"), std::string::npos) << folder;
    EXPECT_TRUE(std::filesystem::exists(path("camp/models") + "/" + folder + ".json")) << folder;
    EXPECT_NE(html.find("href='models/" + folder + ".json'"), std::string::npos) << folder;
    ++runs;
  }
  EXPECT_EQ(runs, 17);
  // A kept run is a run log the other commands take: its model validates on it as reported.
  const Result v = excite("validate --json " + path("camp/models/04-prbsUnc.json") + " " +
                          path("camp/runs/04-prbsUnc/run.csv"));
  ASSERT_EQ(v.exit_code, 0) << v.out;
  const auto model = nlohmann::json::parse(std::ifstream(path("camp/models/04-prbsUnc.json")));
  EXPECT_NEAR(nlohmann::json::parse(v.out)["outputs"][0]["fit"].get<double>(),
              model["outputs"][0]["fit"].get<double>(), 1e-6);
}
