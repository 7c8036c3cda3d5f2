// SPDX-License-Identifier: MIT
// Closed-loop intervals are honest (issue 41 §3): over 100 seeds of woodberry2x2 under the
// example decentralised PI, the nominal 95 % interval K ± 1.96·SE(K) of each gain covers the
// true gain in 90–98 % of the seeds: the direct prediction-error fit with its AR noise model
// (host/identify/noise_model.hpp), with white noise alone and under a coloured output
// disturbance; and the two-stage estimate, its gains and SEs from the instrumental-variable
// step (host/identify/two_stage_uncertainty.hpp). The run prints every element's coverage, the
// spread of (K̂ − K)/SE, the SD of K̂ over the seeds and the RMS of its SE.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "host/identify/closed_loop.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

constexpr int kSeeds = 100;
constexpr Eigen::Index kRows = 2000;

// r: ±1 random binary per CV, switching with probability 1/20 each minute; one fixed signal
// (seed 1234), as a designed plan is: only the noise changes with the seed.
Eigen::MatrixXd reference_signal(Eigen::Index rows) {
  std::mt19937_64 g(1234);
  Eigen::MatrixXd r(rows, 2);
  for (Eigen::Index c = 0; c < 2; ++c) {
    double level = 1.0;
    for (Eigen::Index k = 0; k < rows; ++k) {
      if (g() % 20 == 0) level = -level;
      r(k, c) = level;
    }
  }
  return r;
}

struct Coverage {
  Eigen::Matrix2d covered = Eigen::Matrix2d::Zero();  // seeds whose interval holds the truth
  Eigen::Matrix2d z_sum = Eigen::Matrix2d::Zero();    // Σ (K̂ − K)/SE
  Eigen::Matrix2d z_square = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d k_sum = Eigen::Matrix2d::Zero();  // Σ K̂, Σ K̂², Σ SE²
  Eigen::Matrix2d k_square = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d se_square = Eigen::Matrix2d::Zero();
  double sigma_n_error = 0.0;  // Σ (σ̂_n − σ_n)/σ_n
  int seeds = 0;

  void add(const IdentifiedModel& m, const Eigen::Matrix2d& truth) {
    ++seeds;
    const double sigma_n = Eigen::JacobiSVD<Eigen::Matrix2d>(truth).singularValues()(1);
    const Eigen::Matrix2d estimate = m.static_gain();
    sigma_n_error +=
        Eigen::JacobiSVD<Eigen::Matrix2d>(estimate).singularValues()(1) / sigma_n - 1.0;
    for (int o = 0; o < 2; ++o) {
      for (int i = 0; i < 2; ++i) {
        const ElementEstimate& e = m.element(o, i);
        const double z = (e.value.static_gain() - truth(o, i)) / e.std_error.gain;
        covered(o, i) += std::abs(z) <= 1.96 ? 1.0 : 0.0;
        z_sum(o, i) += z;
        z_square(o, i) += z * z;
        const double k = e.value.static_gain();
        k_sum(o, i) += k;
        k_square(o, i) += k * k;
        se_square(o, i) += e.std_error.gain * e.std_error.gain;
      }
    }
  }
  double share(int o, int i) const { return covered(o, i) / seeds; }
  double overall() const { return covered.sum() / (4.0 * seeds); }
  void print(const char* name) const {
    std::printf("%s: %.1f %% of %d seeds, sigma_n off by %+.1f %% on average\n", name,
                100.0 * overall(), seeds, 100.0 * sigma_n_error / seeds);
    for (int o = 0; o < 2; ++o) {
      for (int i = 0; i < 2; ++i) {
        const double mean = z_sum(o, i) / seeds;
        const double k_mean = k_sum(o, i) / seeds;
        std::printf("  G%d%d %5.1f %%  mean z %+.2f  SD z %.2f  SD of K %.4f  RMS SE %.4f\n", o + 1,
                    i + 1, 100.0 * share(o, i), mean,
                    std::sqrt(z_square(o, i) / seeds - mean * mean),
                    std::sqrt(k_square(o, i) / seeds - k_mean * k_mean),
                    std::sqrt(se_square(o, i) / seeds));
      }
    }
  }
};

struct Both {
  Coverage direct, two_stage;
  std::vector<double> direct_level;  // A(1) = 1 + Σ a_j of each seed's direct noise models
};

// A(1) of the simulator's output noise: a first-order disturbance of std `disturbance_std`,
// pole φ = exp(−T/τ), plus white noise of variance `white`, is the ARMA(1,1) of that pole and
// the zero θ of its innovation form, so A(1) = (1 − φ)/(1 − θ).
double true_level(double disturbance_std, double tau_min, double white) {
  const double phi = std::exp(-1.0 / tau_min);
  const double drive = disturbance_std * disturbance_std * (1.0 - phi * phi);
  const double c0 = drive + white * (1.0 + phi * phi);  // θ/(1 + θ²) = c1/c0
  const double c1 = white * phi;
  const double theta = (c0 / c1 - std::sqrt(c0 * c0 / (c1 * c1) - 4.0)) / 2.0;
  return (1.0 - phi) / (1.0 - theta);
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

// kSeeds closed-loop runs of `rows` rows with white noise of variance 10⁻² and a coloured
// disturbance of std `disturbance_std` (τ 20 min), each identified both ways, every element
// first order.
Both over_seeds(double disturbance_std, Eigen::Index rows = kRows) {
  const auto file = sim::control::load_controller_file(std::string(EXCITE_CONTROL_EXAMPLES) +
                                                       "/woodberry2x2.pi.toml");
  const Eigen::Matrix2d truth = sim::make_plant("woodberry2x2")->static_gain();
  auto model = sim::control::load_model(file);
  const Eigen::MatrixXd g0 = truth;
  ClosedLoopOptions loop;
  loop.mv_min = Eigen::Vector2d(-0.3, -0.3);
  loop.mv_max = Eigen::Vector2d(0.3, 0.3);
  IdentifyOptions options;
  options.structure = Structure::first_order;
  options.max_time_constant_min = 100.0;
  const Eigen::MatrixXd r = reference_signal(rows);
  Both out;
  for (int s = 1; s <= kSeeds; ++s) {
    auto plant = sim::make_plant("woodberry2x2");  // at rest, as the controller
    auto controller = sim::control::make_controller(file, *model, &g0);
    SimulationOptions noise;
    noise.seed = static_cast<std::uint64_t>(s);
    noise.noise_variance = 1e-2;
    noise.disturbance_std = disturbance_std;
    noise.disturbance_tau_min = 20.0;
    const SimulatedRun run = simulate_closed_loop(r, "r", 1.0, *plant, *controller, loop, noise);
    // Every row scored: a closed-loop run's clamped rows are (run_layout.hpp).
    const ClosedLoopIdentification id =
        identify_closed_loop(run.du, r, run.dy, 1.0, SampleLayout::whole(rows), options);
    out.direct.add(id.direct.model, truth);
    for (const ArNoiseModel& a : id.noise_direct) out.direct_level.push_back(1.0 + a.a.sum());
    out.two_stage.add(id.two_stage.model, truth);
  }
  return out;
}

// Overall 90–98 %, and no element below 85 %.
void expect_calibrated(const Coverage& c) {
  EXPECT_GE(c.overall(), 0.90);
  EXPECT_LE(c.overall(), 0.98);
  for (int o = 0; o < 2; ++o) {
    for (int i = 0; i < 2; ++i) EXPECT_GE(c.share(o, i), 0.85) << "G" << o + 1 << i + 1;
  }
}

TEST(ClosedLoopCalibration, WoodberryUnderPiWithWhiteNoise) {
  const Both b = over_seeds(0.0);
  b.direct.print("direct, white noise");
  b.two_stage.print("two-stage, white noise");
  expect_calibrated(b.direct);
  // The two-stage gains after the instrumental-variable step (two_stage_uncertainty.hpp):
  // measured 94.5 %, SD of z 0.93–1.01 (95.5 %, 0.88–1.05 with Ω over min(200, N/10) lags).
  // Stage 2's own SEs covered 99 % (SD of z 0.3–0.6):
  // they count G(u − û) as noise, and that held a bias where the MVs clamp (README).
  expect_calibrated(b.two_stage);
}

TEST(ClosedLoopCalibration, WoodberryUnderPiWithAColouredDisturbance) {
  const Both b = over_seeds(0.3);
  b.direct.print("direct, coloured disturbance 0.3, tau 20 min");
  b.two_stage.print("two-stage, coloured disturbance 0.3, tau 20 min");
  expect_calibrated(b.direct);
  // Measured 93.8 %, 89–96 % per element (92.5 % with Ω over min(200, N/10) lags; 91.5 % with
  // stage 2's SEs widened by the two-step sandwich; 72.2 % with stage 2's own).
  expect_calibrated(b.two_stage);
}

TEST(ClosedLoopCalibration, WoodberryUnderPiOnAShortRecordTheTwoStageEstimateIsNotBiased) {
  // GIVEN 270 rows, where the adaptive test stops: the default stage 1 affords 20 functions
  // per r channel, and the PI loop's input sensitivity settles over some 100 minutes
  // (integral times 8 and 24 min).
  const Both b = over_seeds(0.0, 270);
  b.direct.print("direct, white noise, 270 rows");
  b.two_stage.print("two-stage, white noise, 270 rows");
  // THEN the two-stage σ_n is within a few % of the truth on average (measured −0.3 % after
  // the instrumental-variable step, −4.3 % before it; the direct fit +0.1 %), and its
  // intervals cover (96.8 %). Stage 2 on a FIR of the 20 lags leaves the rest of the settling
  // in u − û, which it reads as a bias: +11.1 % (FIRs of 40 and 60 lags −4.1 and −5.7 %). On
  // the woodberry2x2 adaptive test with `--method two-stage` that bias had 78 of 100 seeds
  // stop on a model that missed the criterion (host/identify/README.md, "Stage 1: Laguerre
  // functions").
  EXPECT_LT(std::abs(b.two_stage.sigma_n_error / b.two_stage.seeds), 0.07);
  EXPECT_GE(b.two_stage.overall(), 0.90);
  expect_calibrated(b.direct);
}

TEST(ClosedLoopCalibration,
     WoodberryUnderPiOnAShortRecordTheDirectNoiseModelKeepsTheDisturbancesLevel) {
  // GIVEN 540 rows under the coloured disturbance: its time constant fits in the record 27
  // times. On so few rows BIC keeps an AR of order 1 to 3, whose A(1) is well above the
  // disturbance's: it sees less noise at low frequency than there is, where the gains are
  // read, and their SEs come out short.
  const Both b = over_seeds(0.3, 540);
  b.direct.print("direct, coloured disturbance 0.3, tau 20 min, 540 rows");
  b.two_stage.print("two-stage, coloured disturbance 0.3, tau 20 min, 540 rows");
  const double ratio = median(b.direct_level) / true_level(0.3, 20.0, 1e-2);
  std::printf("direct noise models' A(1): median %.2f times the disturbance's\n", ratio);
  // THEN with the ARMA(1,1) among the candidates the median A(1) comes closer to the
  // disturbance's (measured 1.34 times it; 1.47 with the AR alone). It is still above it: on
  // 27 time constants the pole's estimate falls short of 1, and the fitted G takes some of
  // the disturbance's slow part (host/identify/README.md).
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.4);
  // AND the direct fit's intervals come closer to calibrated (measured 88.2 %, 86–91 % per
  // element; 86.5 % with the AR alone; the rest is not calibrated yet, host/identify/
  // README.md, "Not calibrated yet: short records under the coloured disturbance")
  EXPECT_GE(b.direct.overall(), 0.85);
  // The two-stage estimate's come as close (measured 89.8 %, 87–92 % per element; 69–90 %
  // with stage 2's SEs widened by the two-step sandwich).
  EXPECT_GE(b.two_stage.overall(), 0.85);
}

}  // namespace
}  // namespace excite::host
