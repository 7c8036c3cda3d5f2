// SPDX-License-Identifier: MIT
#pragma once
// Gain intervals that hold where the linearisation does not (issue 43 §2): the profile
// likelihood of one gain of a row.
//
// When a row's inputs move together, its output determines the sum of their gains well and
// the split only through the small own parts of the inputs and the elements' different
// dynamics; the output error then has a long valley along the split, with local optima in
// it, and σ̂²(JᵀJ)⁻¹ at the end of a fit describes only the basin the fit ended in (a
// Wood–Berry run with u2 = u1 ± 1.4 % gave K11 = −7.7 ± 0.7, true +12.8, in a basin 78 σ̂²
// above the refit from the truth). A walk from such a basin meets the barrier before the
// true one, so the profile widens honestly only what the basin's own valley allows, and
// a better optimum it meets on the way is kept (inputs_together.hpp says what it achieved).
// The profile does not assume local linearity: the gain is held at values c walking away
// from K̂ and every other parameter of the row refitted (fit_miso's HeldGain), and the
// interval is where the cost rise stays below the χ²₁ 95 % point,
//   S(c) − S(K̂) ≤ 1.96² σ̂²,   σ̂² = S(K̂)/(N − P)
// (the likelihood-ratio interval of a Gaussian output error; Venzon & Moolgavkar 1988,
// Bates & Watts 1988 §6). The profile was chosen over a parametric bootstrap because the
// bootstrap refits from the estimate and stays in its basin when the estimate has the wrong
// split (the case that matters), and costs tens of full fits where the profile costs a
// walk of warm-started ones along the ridge.
//
// A small element's dynamics are poorly determined, and the walk from its basin can miss
// another one: each point of the walk is fitted twice, from the last point and from the
// element with the dynamics of the row's largest response (in its own structure, gain held),
// and the better kept.
// On alatiqi4x4 under its DMC this took G43's coverage from 83 to 87 % (100 seeds).
//
// Along the walk the other gains follow the ridge the data leave free; its direction, the
// change of the row's gains per unit of the held gain, widens the row's gain covariance so
// that σ_i, the directions and the minors' signs (gain_uncertainty.hpp) see the same
// uncertainty, correlated as the data make it (the sum stays known).

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/miso_fit.hpp"

namespace excite::host {

/// One output's fit as fit_miso() takes it.
struct RowProblem {
  const Eigen::MatrixXd& U;
  const Eigen::VectorXd& y;
  const std::vector<int>& inputs;
  double T_min;
  const MisoBounds& bounds;
  int max_iterations;
  const SampleLayout& layout;
  const Eigen::MatrixXd& trend;
};

struct GainInterval {
  double lower = 0.0;  // the profile's 95 % interval of the gain; where the walk did not
  double upper = 0.0;  // reach the χ² bound, the farthest value it reached (…_bounded false)
  bool lower_bounded = true;
  bool upper_bounded = true;
  Eigen::VectorXd ridge;  // d K_row / d K_e along the profile (ridge(e) = 1)
  double root = 1.96;     // the signed root walked to: 1.96, or √χ²_p for a projection
  int fits = 0;           // fit_miso calls the walk made
  // A point of the walk fitted better than the estimate: the estimate was not the row's
  // optimum. The interval is then of no use; the caller refits from `better` and profiles again.
  std::optional<MisoResult> better;
};

/// The profile interval of the gain of element `e` of `fit` (the row's fit on `row`,
/// with standard errors).
GainInterval profile_gain(const RowProblem& row, const MisoResult& fit, int e);

/// The 95 % point of χ²_p for p = 1…7 (an element's free parameters); throws
/// std::invalid_argument for any other p.
double chi_square_95(int p);

/// Why element `est`'s gain interval is projected ("" where it is not): its joint 95 %
/// region reaches K = 0 (linearised: |K̂| < √χ²_p·SE, p its free parameters), or its dynamics
/// are not determined (the delay on its upper bound, the main lag T_p1 or T_n shorter than a
/// sample T_min, or ζ on its lower bound: a small element's fit in a fast basin, its gain read
/// from the fast part of the response). At K = 0 the element's dynamics are not determined at
/// all, and near there, or where they are not determined anyway, the likelihood ratio of K
/// alone is not χ²₁ (weak identification: Dufour, Econometrica 65 (1997) 1365; Andrews and
/// Cheng, Econometrica 80 (2012) 2153), while the projection of the joint region keeps its
/// level whatever the nuisance parameters do.
std::string projection_needed(const ElementEstimate& est, double T_min);

/// Whether the fit's gains are the estimate or a later step takes their bias off, which decides
/// how far a projection reaches (projected_gain_interval, project_gains_near_zero).
enum class ProjectionScope {
  // The fit is the estimate, and its gains keep their bias. A first-order element whose truth
  // is slower biases its gain and, along the ridge, its neighbours': alatiqi4x4's
  // G23 = −0.05/(34.5s+1)² under its DMC, fitted first order in 78 of 100 direct fits, has
  // K̂23 −0.009 and K̂24 1.48 on average there (two lags: −0.054 and 1.528). So a first-order
  // element's projection is the hull of its own region's and of its region in two lags, and
  // the gains tied to it follow its whole width, read as a χ²₁ interval (the direct fit's
  // G24: K ± 1.96·SE covers it in 71 % of the seeds).
  fit_is_final,
  // A later step takes each gain's bias off (the two-stage estimate's instrumental-variable
  // step: the same G24's K ± 1.96·SE covers 83 %). The element's own structure only, and the
  // tied gains follow only what the projection adds beyond its linearised joint region,
  // √χ²_p·SE: with the reach above, G21–G24 covered 98–100 %.
  instrument_step_follows,
};

/// The projection on its gain of element `e`'s joint 95 % region where projection_needed():
/// the profile of the gain walked to S(c) − S(K̂) = χ²_p σ̂² instead of χ²₁ σ̂². A point of
/// the walk that fits better than the estimate (a small element's other basin) counts as
/// inside, and the walk goes on: the interval is then wider than the better optimum's own
/// (never `better`). With `fit_is_final`, a first-order element's interval also holds the
/// projection of its region in two lags (the row refitted with the element in two_poles, p + 1
/// parameters, its own cost the reference). Empty where none is needed and for a row fitted to
/// rounding.
std::optional<GainInterval> projected_gain_interval(
    const RowProblem& row, const MisoResult& fit, int e,
    ProjectionScope scope = ProjectionScope::fit_is_final);

/// Sets ElementEstimate::projected_gain on the elements of `fit` that a projection reaches:
/// each gain projection_needed() names gets its projected interval, and each other gain of
/// the row the interval K ± 1.96·SE' of the row's covariance widened along each projection's
/// ridge (how far: `scope`): the gains that the data tie to a projected one (the sum stays
/// known) follow it. A gain whose SE' is within 1 % of its SE keeps none. Reported beside the
/// χ²₁ covariance, never folded into it: the adaptive test's stop rule and G(0)'s uncertainty
/// propagate the covariance (host/identify/README.md, "Closed-loop runs").
void project_gains_near_zero(const RowProblem& row, MisoResult& fit,
                             ProjectionScope scope = ProjectionScope::fit_is_final);

/// Whether gain e of a row's fit is profiled.
using ProfileChoice = std::function<bool(const MisoResult& fit, int e)>;

/// Each estimated gain of `fit` that `profiled` names, profiled: a better optimum found on a
/// walk replaces the fit and the profiles start again from it (at most twice; after that a
/// gain whose walk still finds one keeps its linearised interval), and the row's covariance
/// is widened along each ridge. A row fitted to rounding (noise-free data in the model class)
/// is returned as it is: its gains are exact, and its walks would compare rounding noise.
MisoResult profile_gains(const RowProblem& row, MisoResult fit, const ProfileChoice& profiled);

/// A gain near zero: fewer than 1/kPoorlyDetermined = 8 standard errors from it (its
/// linearised 95 % interval wider than ±25 % of the gain). K = 0 is the element's singular
/// point — there its dynamics are not determined at all — so near it the output error is far
/// from quadratic in K and the linearised interval is stated in whatever basin the small
/// element's dynamics fell into. Measured on alatiqi4x4 under its DMC (100 seeds, the direct
/// fit; host/identify/README.md "Closed-loop runs"): G23 = −0.05 covered 29 % and G43 = −0.1
/// 77 % with the linearised intervals; G13 = −0.25 and G14 = −0.49, 4–8 SE from zero, 84 and
/// 86 %. With these gains profiled: 65, 87, 91 and 92 %.
constexpr double kPoorlyDetermined = 0.125;
bool poorly_determined(const ElementEstimate& e);

/// The estimated element of `fit` whose part of the row's output is largest, |K|·‖u‖ (-1:
/// none is estimated).
Eigen::Index largest_response(const RowProblem& row, const MisoResult& fit);

/// ‖y − ŷ‖² over the scored rows of `row`'s layout.
double row_cost(const RowProblem& row, const MisoResult& fit);
/// The degrees of freedom of that cost: the scored rows less the trend's columns and the
/// elements' free parameters (σ̂² = row_cost / row_dof).
double row_dof(const RowProblem& row, const MisoResult& fit);

/// The row's gain covariance widened along `interval.ridge` until the variance of gain e is
/// ((upper − lower)/(2·root))² (never narrowed): root 1.96 reads the interval as a χ²₁ one
/// (a profile's; a projection's whole width), `interval.root` only what it adds beyond its
/// linearised region. Every element's std_error.gain, its covariance's gain entry and
/// weak_gain status follow.
void widen_along_ridge(MisoResult& fit, int e, const GainInterval& interval, double root = 1.96);

/// The row's gain covariance plus alpha·d dᵀ (nothing for alpha ≤ 0); every element's
/// std_error.gain, its covariance's gain entry, profile_variance (what was added) and
/// weak_gain status follow (never narrowed).
void add_gain_variance(MisoResult& fit, const Eigen::VectorXd& direction, double alpha);

}  // namespace excite::host
