// SPDX-License-Identifier: MIT
// The perturbed true plant (issue 29 §1): every gain, time constant and delay moves, within
// ±X %, the same way for the same seed and differently for another; the designs' plant stays
// nominal; bad values of --perturb are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "host/montecarlo/unit.hpp"
#include "sim/library/library.hpp"
#include "sim/library/perturb.hpp"

namespace mc = excite::host::montecarlo;
using excite::sim::TransferMatrix;

namespace {

// Every gain, factor coefficient and delay of a plant, in a fixed order.
std::vector<double> parameters(const TransferMatrix& g) {
  std::vector<double> out;
  for (int i = 0; i < g.outputs(); ++i) {
    for (int j = 0; j < g.inputs(); ++j) {
      for (const auto& t : g.element(i, j).terms()) {
        out.push_back(t.gain);
        for (const auto* factors : {&t.zeros, &t.poles})
          for (const auto& f : *factors) out.insert(out.end(), f.poly.begin(), f.poly.end());
        out.push_back(t.delay_min);
      }
    }
  }
  return out;
}

}  // namespace

TEST(Perturb, SameSeedSamePlantOtherSeedOtherPlant) {
  const TransferMatrix nominal = excite::sim::library_plant("alatiqi4x4");
  const auto a = parameters(excite::sim::perturbed_plant(nominal, 10.0, 7));
  const auto again = parameters(excite::sim::perturbed_plant(nominal, 10.0, 7));
  const auto other = parameters(excite::sim::perturbed_plant(nominal, 10.0, 8));
  ASSERT_EQ(a.size(), parameters(nominal).size());
  EXPECT_EQ(a, again);  // bit for bit
  EXPECT_NE(a, other);
  EXPECT_EQ(parameters(excite::sim::perturbed_plant(nominal, 0.0, 7)), parameters(nominal));
}

TEST(Perturb, EveryGainTimeConstantAndDelayMovesWithinTheBound) {
  const TransferMatrix nominal = excite::sim::library_plant("alatiqi4x4");
  const TransferMatrix g = excite::sim::perturbed_plant(nominal, 10.0, 3);
  int moved = 0, checked = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      SCOPED_TRACE("g" + std::to_string(i + 1) + std::to_string(j + 1));
      const auto& n = nominal.element(i, j).terms();
      const auto& p = g.element(i, j).terms();
      ASSERT_EQ(n.size(), p.size());
      for (std::size_t k = 0; k < n.size(); ++k) {
        // G(0) of the element, a first-order time constant, the delay: each a factor in
        // [0.9, 1.1) of the nominal, and not 1.
        const auto ratio_ok = [&](double nominal_value, double value) {
          const double r = value / nominal_value;
          EXPECT_GE(r, 0.9);
          EXPECT_LT(r, 1.1);
          moved += r != 1.0 ? 1 : 0;
          ++checked;
        };
        ratio_ok(n[k].gain, p[k].gain);
        ratio_ok(n[k].delay_min, p[k].delay_min);
        ASSERT_EQ(n[k].poles.size(), p[k].poles.size());
        for (std::size_t f = 0; f < n[k].poles.size(); ++f) {
          const auto& np = n[k].poles[f].poly;
          const auto& pp = p[k].poles[f].poly;
          ASSERT_EQ(np.size(), pp.size());
          EXPECT_EQ(pp[0], np[0]);            // the static gain is the gain's alone
          ratio_ok(np[1], pp[1]);             // τ
          if (np.size() == 3) {               // a second-order factor keeps its damping:
            const double f1 = pp[1] / np[1];  // a_k f^k
            EXPECT_NEAR(pp[2] / np[2], f1 * f1, 1e-12);
          }
        }
      }
    }
  }
  EXPECT_EQ(moved, checked);
  // The plant's G(0) differs from the nominal in every element, within ±10 %.
  const Eigen::MatrixXd ratio = g.static_gain().cwiseQuotient(nominal.static_gain());
  EXPECT_TRUE((ratio.array() != 1.0).all()) << ratio;
  EXPECT_LE(ratio.maxCoeff(), 1.1);
  EXPECT_GE(ratio.minCoeff(), 0.9);
}

TEST(Perturb, BadValuesAreRefusedNamingTheOptionValueAndRange) {
  for (const std::string text : {"-1", "100", "250", "abc", "", "5%", "nan", "inf"}) {
    SCOPED_TRACE(text);
    try {
      excite::sim::parse_perturb(text);
      FAIL() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--perturb = " + text +
                                           ", expected a number of percent, 0 <= X < 100"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(excite::sim::parse_perturb("12.5"), 12.5);
  EXPECT_EQ(excite::sim::parse_perturb("0"), 0.0);
  mc::Config c;
  c.plant = "colaA";
  c.seeds = 1;
  c.perturb_percent = 5.0;
  try {
    mc::normalise(c);
    FAIL() << "a column was perturbed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--perturb = 5 on plant colaA, expected 0"),
              std::string::npos)
        << e.what();
  }
}

// A unit of a perturbed run simulates the seed's perturbed plant and judges against it; the
// designs stay the nominal ones.
TEST(Perturb, AUnitRunsOnTheSeedsPerturbedPlantWithTheNominalDesign) {
  mc::Config config;
  config.plant = "woodberry2x2";
  config.designs = {"prbsUnc", "prbsSimDir"};
  config.seeds = 1;
  config.first_seed = 4;
  config.noise_variance = 5e-4;
  config.length_step_percent = 0;
  mc::normalise(config);
  mc::Config perturbed_config = config;
  perturbed_config.perturb_percent = 20.0;
  const auto nominal = mc::prepare(config, 1);
  const auto perturbed = mc::prepare(perturbed_config, 1);
  // The designs are the nominal plant's either way.
  ASSERT_EQ(nominal->designs[1].table.rows(), perturbed->designs[1].table.rows());
  EXPECT_TRUE(nominal->designs[1].table == perturbed->designs[1].table);

  const mc::UnitResult a = mc::run_unit(*nominal, {1, 4, 0});
  const mc::UnitResult b = mc::run_unit(*perturbed, {1, 4, 0});
  const mc::UnitResult b_again = mc::run_unit(*perturbed, {1, 4, 0});
  EXPECT_TRUE(a.true_gain.empty());
  const Eigen::MatrixXd truth =
      excite::sim::perturbed_plant(excite::sim::library_plant("woodberry2x2"), 20.0, 4)
          .static_gain();
  ASSERT_EQ(b.true_gain.size(), 4U);
  for (Eigen::Index k = 0; k < 4; ++k)
    EXPECT_EQ(b.true_gain[static_cast<std::size_t>(k)], truth(k / 2, k % 2));
  // Another plant, so another run and another model; the same one again for the same seed.
  EXPECT_NE(a.gain, b.gain);
  EXPECT_NE(a.fit_avg, b.fit_avg);
  EXPECT_EQ(b.gain, b_again.gain);
  EXPECT_EQ(b.crossfit_worst, b_again.crossfit_worst);
  // The identified G(0) follows the perturbed plant: each element nearer the perturbed truth
  // than the nominal where they differ by more than 5 %.
  const Eigen::MatrixXd nominal_gain = excite::sim::library_plant("woodberry2x2").static_gain();
  for (Eigen::Index k = 0; k < 4; ++k) {
    const double t = truth(k / 2, k % 2), n = nominal_gain(k / 2, k % 2);
    if (std::abs(t - n) < 0.05 * std::abs(n)) continue;
    const double identified = b.gain[static_cast<std::size_t>(k)];
    EXPECT_LT(std::abs(identified - t), std::abs(identified - n)) << "element " << k;
  }
}
