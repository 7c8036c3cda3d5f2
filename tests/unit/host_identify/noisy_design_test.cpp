// SPDX-License-Identifier: MIT
// The identifier on a noisy run whose plant is inside the model structure (6.1.1): the
// global minimum of the output error is then near the truth, and the identifier must find
// it — every row fits about as well as the noise allows, every element near its true gain.
//
// Regression: woodberry2x2, preset msGlmSimDir, noise variance 5e-4, seed 17 (exactly what
// `excite design -q --plant woodberry2x2 --preset msGlmSimDir` then `excite simulate
// --noise-var 5e-4 --seed 17` produce: the design's plan run by host/simulate, i.e. the
// plant's simulate() plus sim::MeasurementNoise). Row y2 used to end in a local minimum
// (fit 46.3 %, element (y2, u1) collapsed to K = 0.28 with T_d ≈ 0, T_p ≈ 6e-5 min) while
// the truth, 6.6 e^{−7s}/(10.9 s + 1), fits ≈ 96–97 %.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/validate.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/parse_element.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

struct NoisyCase {
  const char* plant;
  const char* preset;
  double noise_variance;
  std::uint64_t seed;
};

class NoisyDesign : public ::testing::TestWithParam<NoisyCase> {};

TEST_P(NoisyDesign, EveryRowReachesTheGlobalMinimumNearTheTruth) {
  const NoisyCase c = GetParam();
  const PriorKnowledge prior = case_study(c.plant);
  const Design design = design_preset(prior, find_preset(c.preset), 0);
  ASSERT_NE(design.plan, nullptr);
  const auto plant = sim::make_plant(c.plant);
  SimulationOptions sim_options;
  sim_options.noise_variance = c.noise_variance;
  sim_options.seed = c.seed;
  const SimulatedRun run = simulate_plan(*design.plan, c.preset, *plant, sim_options);

  IdentifyOptions options;
  options.max_time_constant_min = prior.beta * prior.tau_high_min;  // SPEC §6 default
  const IdentificationResult r = identify(run.du, run.dy, run.sample_time_min, options);

  // Fit of the true model on the same data: the level the global minimum reaches or beats.
  const sim::TransferMatrix g = sim::library_plant(c.plant);
  std::printf("%s %s noise %g seed %llu: fit %%", c.plant, c.preset, c.noise_variance,
              static_cast<unsigned long long>(c.seed));
  for (const OutputFit& f : r.fits) std::printf(" %.3f", f.fit_percent);
  // The true model's fit on the same data (the level of the global minimum): the identified
  // model must reach it to within 0.5 points (a local minimum is several points below).
  const Eigen::MatrixXd Y_true = sim::DiscretePlant(g, run.sample_time_min).simulate(run.du);
  std::printf("; the true model fits");
  std::vector<double> true_fit;
  for (Eigen::Index j = 0; j < run.dy.cols(); ++j) {
    const Eigen::VectorXd y = run.dy.col(j);
    const Eigen::VectorXd y_true = Y_true.col(j);
    true_fit.push_back(fit_percent(y, y_true));
    std::printf(" %.3f", true_fit.back());
  }
  std::printf("\n");
  ASSERT_EQ(r.fits.size(), true_fit.size());
  for (std::size_t j = 0; j < r.fits.size(); ++j) {
    EXPECT_GE(r.fits[j].fit_percent, true_fit[j] - 0.5) << "output " << j + 1;
  }
  // Every gain within ±2σ of the truth (σ the identifier's own standard error).
  const Eigen::MatrixXd truth = g.static_gain();
  for (int j = 0; j < r.model.outputs; ++j) {
    for (int i = 0; i < r.model.inputs; ++i) {
      const ElementEstimate& e = r.model.element(j, i);
      EXPECT_EQ(e.status, ElementStatus::identified) << "element (" << j + 1 << "," << i + 1 << ")";
      ASSERT_TRUE(std::isfinite(e.std_error.gain)) << "element (" << j + 1 << "," << i + 1 << ")";
      EXPECT_LE(std::abs(e.value.gain - truth(j, i)), 2.0 * e.std_error.gain)
          << "element (" << j + 1 << "," << i + 1 << "): K = " << e.value.gain << " ± "
          << e.std_error.gain << ", true " << truth(j, i);
    }
  }
}

std::string noisy_case_name(const ::testing::TestParamInfo<NoisyCase>& info) {
  return std::string(info.param.plant) + "_" + info.param.preset + "_seed" +
         std::to_string(info.param.seed);
}

INSTANTIATE_TEST_SUITE_P(Woodberry, NoisyDesign,
                         ::testing::Values(NoisyCase{"woodberry2x2", "msGlmSimDir", 5e-4, 17},
                                           NoisyCase{"woodberry2x2", "msGlmSimDir", 5e-4, 18}),
                         noisy_case_name);

// Output y4 of `g` (alatiqi4x4 with elements of row y4 replaced) under the case study's
// prbsSimDir design, noise 5e-4 and `seed`, identified alone (its noise is the whole plant's
// run's), and the true model's noise-free output on the same inputs.
struct RowFour {
  IdentificationResult result;
  Eigen::VectorXd y;       // measured
  Eigen::VectorXd y_true;  // the true model, noise-free
  double noise_variance = 5e-4;
};

RowFour identify_row_four(const sim::TransferMatrix& g, std::uint64_t seed) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const Design design = design_preset(prior, find_preset("prbsSimDir"), 0);
  if (design.plan == nullptr) throw std::logic_error("prbsSimDir has no plan");
  const auto plant = sim::make_linear_plant("alatiqi4x4", g);
  RowFour out;
  SimulationOptions sim_options;
  sim_options.noise_variance = out.noise_variance;
  sim_options.seed = seed;
  const SimulatedRun run = simulate_plan(*design.plan, "prbsSimDir", *plant, sim_options);
  IdentifyOptions options;
  options.max_time_constant_min = prior.beta * prior.tau_high_min;
  out.y = run.dy.col(3);
  out.result = identify(run.du, Eigen::MatrixXd(out.y), run.sample_time_min, options);
  out.y_true = sim::DiscretePlant(g, run.sample_time_min).simulate(run.du).col(3);
  return out;
}

// A plant a little off the library's: alatiqi4x4 with (y4, u2)'s delay 0.52 min instead of
// 0.02 (the same run otherwise: prbsSimDir, noise 5e-4, seed 8). Under the directional
// design's correlated inputs the structure search ended with (y4, u2) =
// 14 (10s+1) e^{−0.52s} / ((45s+1)(17.4s²+3s+1)) in first order and its oscillating pair on
// the tiny (y4, u3): row y4 at 85.4 % with a residual far from white (Q = 1.2·10⁴) and
// dependent on u2 — over 60 seeds, 14 rows ended worse than the refit from the truth. The
// residual is the evidence that restarts the element it depends on
// (structure_search.cpp, restart_misplaced_dynamics).
TEST(MisplacedDynamics, AnElementTheResidualDependsOnIsRestartedUntilTheResidualIsWhite) {
  sim::TransferMatrix g = sim::library_plant("alatiqi4x4");
  g.set_element(3, 1, sim::parse_element("14(10s+1) e^-0.52s / ((45s+1)(17.4s^2+3s+1))"));
  const RowFour row = identify_row_four(g, 8);

  const OutputFit& fit = row.result.fits.front();
  EXPECT_GE(fit.fit_percent, fit_percent(row.y, row.y_true) - 0.5);
  EXPECT_TRUE(fit.residual_tests.white()) << "Q = " << fit.residual_tests.whiteness;
  const ElementEstimate& lead = row.result.model.element(0, 1);
  EXPECT_EQ(lead.value.structure, Structure::underdamped_lag_zero);
  EXPECT_LE(std::abs(lead.value.gain - 14.0), 1.96 * lead.std_error.gain) << lead.value.gain;
}

// No oscillating pair faster than the Nyquist frequency (miso_fit.hpp, natural_period_floor).
// alatiqi4x4 with its row y4 within ±20 % of the library's (gains, lags, delays drawn once),
// prbsSimDir, noise 5e-4, seed 20: the search ended with (y4, u4), two lags, underdamped at
// T_n = 0.161 min and ζ = 0.05 — a mode above π/T that the samples alias to a slower one —
// 73 noise variances worse than the true model; over 50 seeds 4 rows did so.
TEST(NyquistFloor, NoElementEndsWithAnOscillatingPairFasterThanTheSamples) {
  sim::TransferMatrix g = sim::library_plant("alatiqi4x4");
  const char* drawn[] = {"-11.16 e^-3.292s / ((48.7s+1)(6.12s+1))",
                         "16.14(10.27s+1) e^-0.2537s / ((52.57s+1)(17.4s^2+3s+1))",
                         "-0.109 e^-0.1606s / ((29.38s+1)(5.399s+1))",
                         "3.89 e^-0.832s / ((55.9s+1)(5.82s+1))"};
  for (int i = 0; i < 4; ++i) g.set_element(3, i, sim::parse_element(drawn[i]));
  const RowFour row = identify_row_four(g, 20);

  for (int i = 0; i < 4; ++i) {
    const ElementModel& e = row.result.model.element(0, i).value;
    if (is_free(e.structure, kNatural)) {
      EXPECT_GE(e.natural_min, 1.0 / std::numbers::pi) << "(y4, u" << i + 1 << ")";  // T = 1 min
    }
  }
  // The true model is in the structures: the search's end fits at least as well as it, to
  // within the BIC price of one parameter (ln M noise variances).
  const auto M = static_cast<double>(row.y.size());
  const double rms = row.result.fits.front().residual_rms;
  const double sse_identified = M * rms * rms;
  const double sse_true = (row.y - row.y_true).squaredNorm();
  EXPECT_LE(sse_identified, sse_true + std::log(M) * row.noise_variance)
      << "identified " << sse_identified << ", true model " << sse_true;
}

}  // namespace
}  // namespace excite::host
