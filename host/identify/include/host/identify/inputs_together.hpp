// SPDX-License-Identifier: MIT
#pragma once
// Inputs that move together (issue 43): the screen of one output row's inputs, and what it
// changes in the row's fit.
//
// The screen (input_screen.hpp, input_separation) is taken twice and the worse kept per
// input: on the inputs as moved, and on the inputs as the row's fitted elements filter them
// (the unit-gain responses, the regressors of the row's gains). Measured on Wood–Berry with
// u2 = √(1 − ρ²)·u1 + ρ·(its own PRBS), 100 seeds (tests/integration/host_calibration,
// collinear_test.cpp):
//  - ρ = 10 % and 30 %: the linearised intervals already cover 93–98 % and σ_min 94–95 %;
//    below kTogether the row names the inputs, and nothing else changes;
//  - ρ = 1 %: the fit ended in a basin 50–500 σ̂² above the refit from the truth in most
//    rows (the data determine the split through the elements' different dynamics, and the
//    search did not find it), its intervals covering 0–6 %, and 61–87 of 100 seeds graded
//    A or B with the truth outside. Below kCannotSplit the row gets more starts
//    (ResponseBank::choose_shared, choose_pair, and for a pair the starts from each input's
//    own part and the exchanged start, own_part_start.hpp), the profile of each such gain
//    (gain_profile.hpp: a better optimum on its walk is kept), the other optima its starts
//    ended in within the likelihood-ratio bound (cover_other_optima()), the own-part floor
//    (own_part_floor()) and at most grade C (grade_together()): confident and wrong fell from
//    61–87 to 0–3 seeds in 100 per element; coverage rose to 22–83 % and, with the own-part
//    starts and the other optima, to 95–97 % (σ_min 95 %). alatiqi4x4's (u1, u2) at 1 %:
//    90.5 % pooled with row y3 at 67–68 %, and 94.8 % (y3 94 %) with the starts along the
//    combination (OwnPartStarts::shared) and the other optima's neighbourhoods.

#include <string>

#include "host/identify/gain_profile.hpp"
#include "host/identify/input_screen.hpp"

namespace excite::host {

/// Below this own part (√(1 − R²) of an input's movement on the others': 96 % of its
/// movement is theirs) a row names the input, the inputs it moves with and the gains'
/// combination the data determine.
constexpr double kTogether = 0.2;
/// Below this own part the split of the gains rests on the elements' dynamics alone: the
/// extra starts, the profile and the own-part floor. The directional designs stay above it
/// (alatiqi4x4 prbsSimDir: 3.5–21 %, its linearised intervals calibrated at 93.5 %).
constexpr double kCannotSplit = 0.02;

/// The screen of row `row`'s inputs after its fit (`fit`'s elements filter them), over the
/// scored rows.
InputSeparation row_separation(const RowProblem& row, const MisoResult& fit);

/// The gains of a row whose linearised intervals do not hold, profiled (profile_gains(): a
/// better optimum found on a walk replaces the fit and the profiles start again from it, at
/// most twice; the row's covariance widened along each ridge): each gain whose input is
/// below kCannotSplit in `separation`, and each gain near zero (poorly_determined(),
/// gain_profile.hpp). A row with an input below kCannotSplit then gets the own-part floor.
/// Returns `fit` unchanged for a row with neither.
MisoResult profile_doubtful_gains(const RowProblem& row, MisoResult fit,
                                  const InputSeparation& separation);

/// The covariance of the row's gains that the inputs' own parts alone support: the row as a
/// linear regression on its inputs all filtered by one response (its largest element's, unit
/// gain), σ̂²(ZᵀZ)⁻¹, leaving out what the elements' different dynamics add. The row's
/// covariance is widened along that matrix's largest-variance direction to its variance
/// there.
void own_part_floor(const RowProblem& row, MisoResult& fit);

/// A local optimum of a row's output error that one of its starts ended in: the elements'
/// gains, the cost and the gains' linearised standard errors there (NaN or empty: not known).
struct RowOptimum {
  Eigen::VectorXd gains;
  double sse = 0.0;
  Eigen::VectorXd se;
};

/// The gains' likelihood-ratio 95 % set holds every optimum whose cost is within 1.96² σ̂²
/// of the least one found, and around each such optimum the values whose cost rise stays
/// below the bound; a profile walk from one basin does not reach the others when the split
/// is multimodal. For a row with an input below kCannotSplit in `separation`, the row's gain
/// covariance is widened along K − K̂ of each such optimum in `optima` (the ends of the row's
/// starts, one model class), rise r σ̂² above the least, until the gains of those inputs
/// reach past it by 1.96·√(1 − r/1.96²) of their SEs there (the estimate's where those are
/// not known). Reaching only the optimum itself left alatiqi4x4's row y3 at a 1 % own part
/// covering 81–83 % (100 seeds), the truth's basin 0.5–3.6 σ̂² above the least in the seeds
/// checked that missed; reaching past it, 94 %.
void cover_other_optima(const RowProblem& row, MisoResult& fit, const InputSeparation& separation,
                        const std::vector<RowOptimum>& optima);

/// For an engineer: each input of the row below kTogether, the inputs it moves with and the
/// gains' combination the data determine; "" when every input moves enough on its own.
/// Inputs are named "input N", N = inputs[e] + 1.
std::string describe_together(const std::vector<int>& inputs, const InputSeparation& separation);

/// Grades at most C, with the reason, each element of `row` (row[i]: the element of input i)
/// whose input is below kCannotSplit: the split rests on the dynamics alone (on alatiqi4x4's
/// u1, u2 on 6 min of delay), and an interval is only as good as the search that found the
/// basins (96–97 % on Wood–Berry, 91–100 % on alatiqi4x4 over 100 seeds).
/// `usable` maps the separation's entries to inputs.
void grade_together(const std::vector<ElementEstimate*>& row, const std::vector<int>& usable,
                    const InputSeparation& separation);

}  // namespace excite::host
