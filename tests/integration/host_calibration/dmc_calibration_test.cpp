// SPDX-License-Identifier: MIT
// The reported 95 % intervals of a closed-loop identification are honest on alatiqi4x4 under
// its example DMC (issue 41 §3): over 100 seeds, each gain's reported interval (model.hpp,
// gain_interval_95: K ± 1.96·SE, or wider where a projection reaches it) covers the true gain
// in 90–98 % of the seeds overall and in 88–98 % for every gain, for both estimates on the
// same runs: the two-stage estimate (the default) and the direct prediction-error fit with
// its noise model. Under the DMC every MV moves with the others (u ≈ G(0)⁻¹ r), and the row
// y2 splits G23 = −0.05 from G24 = 1.53 through little own movement: there K ± 1.96·SE alone
// covers G23 in about half the seeds and G24 in 71–75 % (the direct fit; host/identify/
// README.md "The reported 95 % interval"); the projection of G23's joint region, which
// reaches K = 0, is what covers both.
//
// The stop rule and G(0)'s uncertainty read the covariance, not the reported intervals, and
// the covariance is short for G23 and G24. What they read of it is σ_n, v_n and the minors,
// and those do not see that shortfall: u moves mostly along v_n (the DMC inverts G(0), and
// 1/σ_n is its largest gain), so the data determine G(0)·v_n, and the ridge that ties G24 to
// G23 (K24 + 1.15·K23 determined; v_n's u3 and u4 parts are in the ratio 1.153) moves σ_n by
// 0.0017 per unit of K23 along it, against 0.68 for K23 alone. The test checks that too:
// σ̂_n ± 1.96·SE(σ_n) holds the true σ_n in at least 90 % of the seeds, and no minor whose
// interval excludes 0 has the wrong sign in more than 5 % of them. "feedback bias suspected",
// which reads the reported intervals (closed_loop.hpp gain_disagreements), fires in at most
// 10 % of the seeds: both estimates are consistent here.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "host/identify/closed_loop.hpp"
#include "host/identify/gain_uncertainty.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

constexpr int kSeeds = 100;
constexpr int kThreads = 2;
constexpr Eigen::Index kRows = 4410;  // the bench's design at the loop's pace
constexpr double kAmplitude = 0.055;  // 0.1 of the CV test limits ±0.55

// r: ±kAmplitude random binary per CV, switching with probability 1/70 each minute (the
// loop's pace: T_sw = 70 min); one fixed signal (seed 1234): only the noise changes.
Eigen::MatrixXd reference_signal() {
  std::mt19937_64 g(1234);
  Eigen::MatrixXd r(kRows, 4);
  for (Eigen::Index c = 0; c < 4; ++c) {
    double level = kAmplitude;
    for (Eigen::Index k = 0; k < kRows; ++k) {
      if (g() % 70 == 0) level = -level;
      r(k, c) = level;
    }
  }
  return r;
}

struct Coverage {
  Eigen::Matrix4d by_se = Eigen::Matrix4d::Zero();      // seeds whose K ± 1.96·SE holds K
  Eigen::Matrix4d reported = Eigen::Matrix4d::Zero();   // seeds whose reported interval does
  Eigen::Matrix4d projected = Eigen::Matrix4d::Zero();  // seeds with a projected interval
  int seeds = 0;
  int sigma_n_covered = 0;   // seeds whose σ̂_n ± 1.96·SE(σ_n) holds the true σ_n
  int sigma_n_judged = 0;    // seeds with G(0)'s uncertainty
  int minor_sign_wrong = 0;  // seeds with a minor whose interval excludes 0 on the wrong side

  void add(const IdentificationResult& id, const Eigen::Matrix4d& truth,
           const GainUncertainty& true_g0) {
    ++seeds;
    add_directions(id, true_g0);
    const IdentifiedModel& m = id.model;
    for (int o = 0; o < 4; ++o) {
      for (int i = 0; i < 4; ++i) {
        const ElementEstimate& e = m.element(o, i);
        const double K = e.value.gain, t = truth(o, i);
        by_se(o, i) += std::abs(K - t) <= 1.96 * e.std_error.gain ? 1.0 : 0.0;
        const GainBounds b = gain_interval_95(e);
        reported(o, i) += b.lower <= t && t <= b.upper ? 1.0 : 0.0;
        projected(o, i) += e.projected_gain ? 1.0 : 0.0;
      }
    }
  }

  // What the stop rule reads of the covariance (host/adaptive/confidence.hpp): σ_n and the
  // minors, from IdentificationResult::gain_uncertainty.
  void add_directions(const IdentificationResult& id, const GainUncertainty& true_g0) {
    if (!id.gain_uncertainty) return;
    const GainUncertainty& u = *id.gain_uncertainty;
    ++sigma_n_judged;
    const Eigen::Index n = u.singular_values.size() - 1;
    sigma_n_covered +=
        std::abs(u.singular_values(n) - true_g0.singular_values(n)) <= 1.96 * u.singular_value_se(n)
            ? 1
            : 0;
    bool wrong = false;
    for (std::size_t k = 0; k < u.principal_minors.size(); ++k) {
      const PrincipalMinor& m = u.principal_minors[k];
      wrong |= !m.sign_uncertain && m.value * true_g0.principal_minors[k].value < 0.0;
    }
    minor_sign_wrong += wrong ? 1 : 0;
  }
};

void print(const char* name, const Coverage& c) {
  std::printf(
      "alatiqi4x4 under its DMC, %s, %d seeds: K +- 1.96 SE covers %.1f %%, the reported "
      "interval %.1f %%\n",
      name, c.seeds, 100.0 * c.by_se.sum() / (16.0 * c.seeds),
      100.0 * c.reported.sum() / (16.0 * c.seeds));
  std::printf(
      "  sigma_n +- 1.96 SE holds the true sigma_n in %d of %d seeds; a minor's sign "
      "wrong though its interval excludes 0 in %d\n",
      c.sigma_n_covered, c.sigma_n_judged, c.minor_sign_wrong);
  for (int o = 0; o < 4; ++o) {
    for (int i = 0; i < 4; ++i) {
      std::printf("  G%d%d %5.1f %% (K +- 1.96 SE %5.1f %%, %3.0f projected)\n", o + 1, i + 1,
                  100.0 * c.reported(o, i) / c.seeds, 100.0 * c.by_se(o, i) / c.seeds,
                  c.projected(o, i));
    }
  }
}

// 90–98 % overall; every gain at 88 % or more, and none taken above 98 % by a projection
// (K ± 1.96·SE alone may go there). Each gain's count over 100 seeds has an SD of 2.2 points
// at a true 95 %, so even calibrated intervals leave about one gain of 16 outside 90–98 %
// (P 2.8 % below 90, 3.7 % above 98): hence the floor of 88 %.
void expect_calibrated(const Coverage& c) {
  const double overall = c.reported.sum() / (16.0 * c.seeds);
  EXPECT_GE(overall, 0.90);
  EXPECT_LE(overall, 0.98);
  for (int o = 0; o < 4; ++o) {
    for (int i = 0; i < 4; ++i) {
      EXPECT_GE(c.reported(o, i) / c.seeds, 0.88) << "G" << o + 1 << i + 1;
      EXPECT_LE(c.reported(o, i), std::max(0.98 * c.seeds, c.by_se(o, i))) << "G" << o + 1 << i + 1;
    }
  }
  // σ_n's interval from the covariance, and the minors' signs: what the stop rule reads. Its
  // short side is what would stop a test wrong; measured 97 of 99 seeds (direct; one without
  // a finite covariance) and 98 of 100 (two-stage), no minor's sign wrong.
  EXPECT_GE(c.sigma_n_judged, c.seeds - 2);
  EXPECT_GE(c.sigma_n_covered, 0.90 * c.sigma_n_judged);
  EXPECT_LE(c.minor_sign_wrong, 0.05 * c.seeds);
}

// "feedback bias suspected" (closed_loop.hpp gain_disagreements) per gain over the seeds, as
// flagged (from the reported intervals) and as K ± 1.96·SE alone would flag it. The DMC's
// model is the plant's and the noise white: both estimates are consistent, and a flag is false.
struct FeedbackBiasFlags {
  Eigen::Matrix4d reported = Eigen::Matrix4d::Zero();
  Eigen::Matrix4d by_se = Eigen::Matrix4d::Zero();
  int seeds_flagged = 0;

  void add(const ClosedLoopIdentification& id) {
    for (const GainDisagreement& d : id.feedback_bias) reported(d.output, d.input) += 1.0;
    seeds_flagged += id.feedback_bias.empty() ? 0 : 1;
    for (int o = 0; o < 4; ++o) {
      for (int i = 0; i < 4; ++i) {
        const ElementEstimate& a = id.two_stage.model.element(o, i);
        const ElementEstimate& b = id.direct.model.element(o, i);
        const double sa = a.std_error.gain, sb = b.std_error.gain;
        by_se(o, i) += std::abs(a.value.gain - b.value.gain) > 2.0 * std::hypot(sa, sb) ? 1.0 : 0.0;
      }
    }
  }
};

TEST(ClosedLoopCalibration, AlatiqiUnderItsDmcTheReportedIntervalsCoverEveryGain) {
  const auto file = sim::control::load_controller_file(std::string(EXCITE_CONTROL_EXAMPLES) +
                                                       "/alatiqi4x4.dmc.toml");
  const Eigen::Matrix4d truth = sim::make_plant("alatiqi4x4")->static_gain();
  const Eigen::MatrixXd g0 = truth;
  const GainUncertainty true_g0 =
      gain_uncertainty(g0, std::vector<Eigen::MatrixXd>(4, Eigen::Matrix4d::Zero()));
  ClosedLoopOptions loop;
  set_controller(loop, file, "alatiqi4x4.dmc.toml");
  IdentifyOptions options;
  options.max_time_constant_min = 150.0;  // β·τ_H of the design, 3 × 50 min
  const Eigen::MatrixXd r = reference_signal();
  Coverage direct, two_stage;
  FeedbackBiasFlags flags;
  std::mutex m;
  std::atomic<int> next{1};
  std::vector<std::thread> pool;
  for (int t = 0; t < kThreads; ++t) {
    pool.emplace_back([&] {
      for (int s = next++; s <= kSeeds; s = next++) {
        auto model = sim::control::load_model(file);
        auto plant = sim::make_plant("alatiqi4x4");
        auto controller = sim::control::make_controller(file, *model, &g0);
        SimulationOptions noise;
        noise.seed = static_cast<std::uint64_t>(s);
        noise.noise_variance = 5e-4;
        const SimulatedRun run =
            simulate_closed_loop(r, "r", 1.0, *plant, *controller, loop, noise);
        const ClosedLoopIdentification id =
            identify_closed_loop(run.du, r, run.dy, 1.0, SampleLayout::whole(kRows), options);
        const std::lock_guard<std::mutex> lock(m);
        direct.add(id.direct, truth, true_g0);
        two_stage.add(id.two_stage, truth, true_g0);
        flags.add(id);
      }
    });
  }
  for (std::thread& t : pool) t.join();
  ASSERT_EQ(direct.seeds, kSeeds);
  print("direct fit", direct);
  print("two-stage estimate", two_stage);
  std::printf("feedback bias suspected in %d of %d seeds; per gain, flagged (by K +- 1.96 SE):",
              flags.seeds_flagged, kSeeds);
  for (int o = 0; o < 4; ++o) {
    for (int i = 0; i < 4; ++i) {
      std::printf(" G%d%d %.0f (%.0f)", o + 1, i + 1, flags.reported(o, i), flags.by_se(o, i));
    }
  }
  std::printf("\n");
  // No bias to flag here: the DMC's model is the plant's and the noise white. Measured 4 of
  // 100 seeds (6 flags of 1 600, G43 in 3). From K ± 1.96·SE alone, as before 2026-12-01,
  // G43 was flagged in 12 seeds and G23 in 5: where a projection widens their reported
  // intervals, their SEs alone are short.
  EXPECT_LE(flags.seeds_flagged, 10);
  // The direct fit. Measured: 95.2 % overall (K ± 1.96·SE 89.9 %), every gain at 88–98 %:
  // G23 98 % (46 %) since its first-order fits are projected in two lags too (84 % before),
  // G24 98 % (75 %), G14 88 % (no projection reaches it: its K ± 1.96·SE alone).
  expect_calibrated(direct);
  // The two-stage estimate (the default). Measured: 95.8 % overall (K ± 1.96·SE 91.4 %), every
  // gain at 91–98 % but G42, whose K ± 1.96·SE alone covers 100 %. With the tied gains carried
  // by the projections' whole width (ProjectionScope::fit_is_final) G22, G24 and G41 were
  // at 99 %.
  expect_calibrated(two_stage);
}

}  // namespace
}  // namespace excite::host
