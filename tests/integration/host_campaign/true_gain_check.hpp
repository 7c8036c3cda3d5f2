// SPDX-License-Identifier: MIT
#pragma once
// An identified model against the true plant it was identified from (campaign_test): G(0)
// element by element within 3 standard errors of the identifier's own, and the gain
// directions (singular vectors of G(0)) within the angle that G(0)'s standard error allows.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "host/campaign/campaign.hpp"

namespace excite::host {

/// Asserts, for experiment `e`:
///  - every element identified with a finite standard error σ_K, and |K̂ − K| ≤ 3 σ_K (the
///    relative error is printed, |K̂ − K| / |K|);
///  - every input and output direction i: sin∠(v̂_i, v_i) ≤ 3 ‖σ_K‖_F / gap_i, and the same for
///    w_i (first-order perturbation of a singular vector: the error of G(0), bounded by the
///    Frobenius norm of the elements' σ, over the distance gap_i from σ_i to the nearest
///    other singular value), capped at 1 (a direction the data cannot fix is not asserted).
inline void expect_gain_and_directions_of_the_plant(const Experiment& e,
                                                    const GainAnalysis& truth) {
  const IdentifiedModel& m = e.identified.model;
  double sigma_norm2 = 0.0;
  double worst_relative = 0.0, worst_in_sigma = 0.0;
  for (int j = 0; j < m.outputs; ++j) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& el = m.element(j, i);
      const double k = truth.gain(j, i);
      ASSERT_TRUE(el.estimated()) << e.name << " element (" << j + 1 << "," << i + 1 << ")";
      ASSERT_TRUE(std::isfinite(el.std_error.gain))
          << e.name << " element (" << j + 1 << "," << i + 1 << ")";
      const double error = std::abs(el.value.gain - k);
      sigma_norm2 += el.std_error.gain * el.std_error.gain;
      worst_relative = std::max(worst_relative, error / std::abs(k));
      worst_in_sigma = std::max(worst_in_sigma, error / el.std_error.gain);
      EXPECT_LE(error, 3.0 * el.std_error.gain)
          << e.name << " element (" << j + 1 << "," << i + 1 << "): K = " << el.value.gain << " ± "
          << el.std_error.gain << ", true " << k;
    }
  }
  ASSERT_TRUE(e.identified.gain.has_value())
      << e.name << ": " << e.identified.gain_unavailable_reason;
  const GainAnalysis& g = *e.identified.gain;
  const Eigen::Index r = truth.singular_values.size();
  ASSERT_EQ(g.singular_values.size(), r) << e.name;
  double worst_angle = 0.0;
  for (Eigen::Index i = 0; i < r; ++i) {
    double gap = INFINITY;
    for (Eigen::Index l = 0; l < r; ++l) {
      if (l != i)
        gap = std::min(gap, std::abs(truth.singular_values(i) - truth.singular_values(l)));
    }
    const double allowed = std::min(1.0, 3.0 * std::sqrt(sigma_norm2) / gap);
    for (const auto& [identified, true_directions, what] :
         {std::tuple{&g.input_directions, &truth.input_directions, "v"},
          std::tuple{&g.output_directions, &truth.output_directions, "w"}}) {
      const double c = std::abs(identified->col(i).dot(true_directions->col(i)));
      const double sine = std::sqrt(std::max(0.0, 1.0 - c * c));
      worst_angle = std::max(worst_angle, sine);
      EXPECT_LE(sine, allowed) << e.name << ": " << what << i + 1 << " off by sin = " << sine
                               << ", allowed " << allowed;
    }
  }
  std::printf(
      "%-16s G(0): worst |dK|/|K| %.3g, worst |dK|/sigma_K %.2f; directions: worst sin %.3g "
      "(||sigma_K|| %.3g)\n",
      e.name.c_str(), worst_relative, worst_in_sigma, worst_angle, std::sqrt(sigma_norm2));
}

}  // namespace excite::host
