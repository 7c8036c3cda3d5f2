// SPDX-License-Identifier: MIT
// IdentifyOptions::start (issue 44, the Monte Carlo length grid warm-started): a fit started
// from an earlier model of the same plant ends where the cold fit ends (same structures, the
// same fit to 1e-6 points, gains within a tenth of a standard error) with fewer Levenberg–
// Marquardt iterations (work counted, not timed); a start that does not fit the data's shape
// falls back to the cold fit; StartUse::polish changes no structure.
#include <gtest/gtest.h>

#include <cmath>

#include "host/identify/identify.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

struct Data {
  Eigen::MatrixXd U, Y;
};

// woodberry2x2-like (two poles and a delay per element), PRBS, noise variance 5e-4.
Data noisy_2x2() {
  const std::vector<ElementModel> G{{12.8, 1.0, 16.7, 2.0},
                                    {-18.9, 3.0, 21.0, 3.0},
                                    {6.6, 7.0, 10.9, 1.5},
                                    {-19.4, 3.0, 14.4, 2.0}};
  Data r;
  r.U = testing::prbs_inputs(2, 7, 4, 40, 1200, 0.1);
  r.Y = testing::plant_outputs(G, 2, 2, 1.0, r.U);
  testing::add_noise(r.Y, 5e-4, 7);
  return r;
}

int iterations(const IdentificationResult& r) {
  int n = 0;
  for (const OutputFit& f : r.fits) n += f.iterations;
  return n;
}

IdentifyOptions options() {
  IdentifyOptions o;
  o.max_time_constant_min = 60.0;
  return o;
}

// The fit on 1200 rows from the model on the first 1000: the cold fit's answer, less work.
TEST(WarmStart, FromAShorterPrefixEndsAtTheColdFitWithFewerIterations) {
  const Data run = noisy_2x2();
  const IdentificationResult shorter =
      identify(run.U.topRows(1000), run.Y.topRows(1000), 1.0, options());
  const IdentificationResult cold = identify(run.U, run.Y, 1.0, options());
  IdentifyOptions warm_options = options();
  warm_options.start = shorter.model;
  const IdentificationResult warm = identify(run.U, run.Y, 1.0, warm_options);
  for (int j = 0; j < 2; ++j) {
    EXPECT_NEAR(warm.fits[static_cast<std::size_t>(j)].fit_percent,
                cold.fits[static_cast<std::size_t>(j)].fit_percent, 1e-6);
    for (int i = 0; i < 2; ++i) {
      const ElementEstimate& w = warm.model.element(j, i);
      const ElementEstimate& c = cold.model.element(j, i);
      EXPECT_EQ(w.value.structure, c.value.structure) << j << i;
      EXPECT_NEAR(w.value.gain, c.value.gain, 0.1 * c.std_error.gain) << j << i;
    }
  }
  EXPECT_LT(iterations(warm), iterations(cold));
}

// Polished only: the start's structures kept, the fit no worse than the start's own on the
// longer data, and fewer iterations than the full warm path.
TEST(WarmStart, PolishKeepsTheStartsStructures) {
  const Data run = noisy_2x2();
  const IdentificationResult shorter =
      identify(run.U.topRows(1000), run.Y.topRows(1000), 1.0, options());
  IdentifyOptions o = options();
  o.start = shorter.model;
  o.start_use = IdentifyOptions::StartUse::polish;
  const IdentificationResult polished = identify(run.U, run.Y, 1.0, o);
  o.start_use = IdentifyOptions::StartUse::first_start;
  const IdentificationResult warm = identify(run.U, run.Y, 1.0, o);
  for (std::size_t e = 0; e < 4; ++e) {
    EXPECT_EQ(polished.model.elements[e].value.structure,
              shorter.model.elements[e].value.structure);
  }
  EXPECT_LE(iterations(polished), iterations(warm));
  ASSERT_TRUE(polished.gain);
  ASSERT_TRUE(warm.gain);
  EXPECT_NEAR(polished.gain->singular_values(1), warm.gain->singular_values(1),
              1e-3 * warm.gain->singular_values(1));
}

// A start of another shape (a 1×1 model for 2×2 data) or with an element not estimated is not
// used: the rows are fitted cold, bit for bit as without it.
TEST(WarmStart, AStartThatDoesNotFitTheDataIsIgnored) {
  const Data run = noisy_2x2();
  const IdentificationResult cold = identify(run.U, run.Y, 1.0, options());
  IdentifyOptions o = options();
  IdentifiedModel other;
  other.inputs = 1;
  other.outputs = 1;
  other.elements.assign(1, cold.model.elements[0]);
  o.start = other;
  const IdentificationResult a = identify(run.U, run.Y, 1.0, o);
  IdentifiedModel unestimated = cold.model;
  unestimated.element(0, 1).status = ElementStatus::input_not_moved;
  o.start = unestimated;
  const IdentificationResult b = identify(run.U, run.Y, 1.0, o);
  for (std::size_t e = 0; e < 4; ++e) {
    EXPECT_EQ(a.model.elements[e].value.gain, cold.model.elements[e].value.gain);
    if (e < 2) {
      EXPECT_EQ(b.model.elements[e].value.gain, cold.model.elements[e].value.gain);
    }
  }
  EXPECT_EQ(iterations(a), iterations(cold));
  EXPECT_EQ(b.fits[0].iterations, cold.fits[0].iterations);  // row 1: (1, 2) not estimated
}

}  // namespace
}  // namespace excite::host
