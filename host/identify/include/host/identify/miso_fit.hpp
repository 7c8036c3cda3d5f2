// SPDX-License-Identifier: MIT
#pragma once
// One output's multi-input single-output fit (SPEC §6): bounded Levenberg–Marquardt on the
// output error of all elements of the row, from the initial elements of the response bank,
// then standard errors and element status.

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "host/identify/bounded_lm.hpp"
#include "host/identify/model.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

struct MisoBounds {
  double max_delay_min = 20.0;
  double max_time_constant_min = 1000.0;
  double min_natural_min = 0.0;  // T_n ≥ this; identify() gives T/π (natural_period_floor)
};

/// The shortest T_n a fit on data sampled every T_min may reach: T/π, an oscillating pair no
/// faster than the Nyquist frequency π/T. A faster pair's sampled response aliases to a
/// slower one, which a fit used to bend an element's response between samples: on alatiqi4x4
/// with its row y4 perturbed by up to ±20 % (noisy_design_test.cpp, `NyquistFloor`), an
/// element of two lags ended underdamped with T_n = 0.16 min and ζ = 0.05 at T = 1 min.
double natural_period_floor(double T_min);

/// The box a parameter is fitted in: K free; T_d in [0, max_delay]; T_p1, T_p2 in
/// [0, max_time_constant]; T_n in [min_natural, max_time_constant]; T_z in
/// [−max_time_constant, max_time_constant]; ζ in [kMinDamping, 1].
struct ParameterRange {
  double lower;
  double upper;
};
ParameterRange parameter_range(int parameter, const MisoBounds& bounds);

struct MisoResult {
  std::vector<ElementEstimate> elements;  // one per entry of `inputs`
  Eigen::MatrixXd gain_covariance;        // m × m: covariance of the elements' gains (the
                                          // row's σ̂²(JᵀJ)⁺); NaN rows/columns on a bound
  Eigen::VectorXd y_hat;                  // simulated output with the estimates
  int iterations = 0;
  bool converged = false;
};

/// Fits y ≈ Σ_e G_e u_{inputs[e]} from `initial` (one element per input of `inputs`, each in
/// its own structure, which the fit keeps: only free_parameters(structure) move) on the
/// scored rows of `layout`, the model simulated from rest at each segment's start, and the
/// trend spanned by the orthonormal columns `trend` (trend_basis(); N × 0 for none) fitted
/// with it by projection. y_hat is the simulation on every row plus the fitted trend.
/// `cost_tolerance`: LmOptions::cost_tolerance of the fit.
/// `uncertainty`: MisoUncertainty::none leaves out what only the standard errors need (the
/// Jacobian at the end and its eigen-decomposition): std_error, covariance and
/// gain_covariance are NaN, at_bound is still set and status is `identified` (a trial fit
/// whose estimates and y_hat alone are used: the same values as with them).
enum class MisoUncertainty { standard_errors, none };
/// `held`: one element's gain held at a value (the box [value, value]) while everything else
/// is fitted: a point of that gain's profile likelihood (gain_profile.hpp).
struct HeldGain {
  int element;  // index into `inputs` / `initial`
  double value;
};
MisoResult fit_miso(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                    const std::vector<int>& inputs, std::vector<ElementModel> initial, double T_min,
                    const MisoBounds& bounds, int max_iterations, const SampleLayout& layout,
                    const Eigen::MatrixXd& trend,
                    double cost_tolerance = LmOptions{}.cost_tolerance,
                    MisoUncertainty uncertainty = MisoUncertainty::standard_errors,
                    std::optional<HeldGain> held = std::nullopt);

/// A fit's elements' gains, in the order of its elements.
Eigen::VectorXd gains_of(const MisoResult& fit);
/// A fit's elements' gain standard errors, in the order of its elements.
Eigen::VectorXd gain_errors_of(const MisoResult& fit);
/// A fit's elements' values (a start for another fit).
std::vector<ElementModel> values_of(const MisoResult& fit);

/// Sets e.status to weak_gain, with its reason, when |K| < 2·SE(K) or SE(K) is infinite
/// (the data barely show the element); leaves it otherwise.
void mark_weak_gain(ElementEstimate& e);

}  // namespace excite::host
