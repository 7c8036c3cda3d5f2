// SPDX-License-Identifier: MIT
#pragma once
// The prediction-error fit with a noise model: the direct method that stays consistent in
// closed loop (issue 41 §3; Ljung, System Identification, 2nd ed., §13.4: the direct method
// is consistent under feedback when the noise model can describe the disturbance; Forssell
// and Ljung, Automatica 35 (1999) 1215; CLOSED-LOOP.md, "Identification under feedback").
//
// Per output o, a Box–Jenkins model with an autoregressive noise model:
//   y_o = Σ_i G_oi u_i + v_o,   A_o(q) v_o = e_o white,   A_o(q) = 1 + a_1 q⁻¹ + … + a_n q⁻ⁿ.
// A_o is an AR fit of order n, or the expansion of an ARMA(1,1) fit (fit_ar_noise): a slow
// disturbance under white measurement noise, the simulator's and a plant's usual case, is an
// ARMA(1,1), and a short record's BIC keeps too short an AR for it. The one-step prediction
// error is
//   ε_o = A_o (y_o − Σ_i G_oi u_i) = A_o y_o − Σ_i G_oi (A_o u_i)
// (G_oi and A_o commute; each segment from rest), so for a fixed A_o minimising Σ ε_o² is the
// output-error fit of identify.hpp on the prefiltered data (A_o u, A_o y_o), and for a fixed
// G it is the least-squares AR fit of the output error. identify_with_noise_model alternates
// the two, starting from A_o = 1 (the output-error fit): each step lowers Σ ε_o² when the
// fit reaches its minimum. Under feedback u carries the controller's answer to past v, which
// biases the output-error fit (A_o = 1) when v is coloured; with A_o right ε_o is white and
// the estimate is consistent.

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/identify.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

/// The ARMA(1,1) noise v = (1 − zero·q⁻¹)/(1 − pole·q⁻¹) e: a first-order disturbance of that
/// pole plus white noise. Its prediction error is ε(k) = v(k) − pole·v(k − 1) + zero·ε(k − 1).
struct ArmaPoleZero {
  double pole = 0.0;  // [0, 1)
  double zero = 0.0;  // [−0.9, 0.9]
};

/// A(q) = 1 + a_1 q⁻¹ + … + a_n q⁻ⁿ, the inverse of the noise filter; n = 0: white noise.
/// For an ARMA(1,1), a is the expansion (1 − pole·q⁻¹)/(1 − zero·q⁻¹) = 1 + Σ_k (zero − pole)
/// zero^(k−1) q⁻ᵏ, cut where the tail's sum of |a_k| is below 10⁻³.
struct ArNoiseModel {
  Eigen::VectorXd a;                                        // a_1 … a_n
  double innovation_variance = 0.0;                         // of e = A(q) v
  std::optional<ArmaPoleZero> arma;                         // set when BIC chose the ARMA(1,1)
  int order() const { return static_cast<int>(a.size()); }  // the prefilter's length
  int parameters() const { return arma ? 2 : order(); }
  std::string name() const;  // "white", "AR(n)" or "ARMA(1,1)"
};

/// A(q) by least squares on v (the output error), chosen by BIC (M ln(RSS/M) + p ln M over
/// the same M rows for every candidate: those whose max_order predecessors lie in their
/// segment and are, with the row itself, scored) among the AR orders 0 … max_order and, when
/// the best AR has order ≥ 1, the ARMA(1,1) (p = 2; fitted by fit_arma11). Each segment's
/// scored mean is removed first (an offset is not noise). Throws std::invalid_argument for a
/// size mismatch or max_order < 0; fewer than 10·(max_order + 1) usable rows lower max_order.
ArNoiseModel fit_ar_noise(const Eigen::VectorXd& v, const SampleLayout& layout, int max_order);

/// The ARMA(1,1) prediction error ε of x (above), each segment from rest.
Eigen::VectorXd arma_prediction_error(const Eigen::VectorXd& x, const ArmaPoleZero& arma,
                                      const SampleLayout& layout);

/// The ARMA(1,1) of least Σ ε² over `rows` of x: a grid of poles 0 … 0.98 by 0.02 and zeros
/// −0.9 … 0.9 by 0.1, then a pattern search from the grid's best, its step halved from 0.01
/// to 10⁻⁵. A grid, because the cost is not convex in the pair (a pole and a zero cancel).
ArmaPoleZero fit_arma11(const Eigen::VectorXd& x, const std::vector<Eigen::Index>& rows,
                        const SampleLayout& layout);

/// How well the record tells the noise model's low-frequency level L² = |H(1)|² (H = 1/A, an
/// ARMA(1,1)'s (1 − zero)/(1 − pole)): a gain's variance is σ_e²·L² over the input's power
/// where that power lies below the noise model's corner, so an SE read from a record that
/// holds few of the disturbance's time constants is itself uncertain (and a stop rule that
/// waits for a short SE picks the records whose L² came out low). Returns the degrees of
/// freedom ν of a χ²_ν/ν with the same relative spread, ν = 2 / Var(ln L²) (Satterthwaite),
/// Var(ln L²) by the delta method from the noise parameters' covariance σ_e² (ZᵀZ)⁻¹, Z
/// their prediction-error sensitivities on v (identify_with_noise_model). An AR(1) of pole φ
/// on N rows gives ν = N(1 − φ)/(2(1 + φ)): 3.7 for φ = 0.951 (τ 20 samples) on 300 rows,
/// 62 on 5 000. v: the output error on `layout`'s rows (each segment's mean is removed).
/// +∞ for white noise (order 0) or where the covariance cannot be formed.
double low_frequency_level_dof(const Eigen::VectorXd& v, const ArNoiseModel& noise,
                               const SampleLayout& layout);

/// X (rows of `layout`) filtered by A(q), each segment from rest: x(k) + Σ_j a_j x(k − j),
/// k − j taken in k's segment only.
Eigen::MatrixXd prefilter(const Eigen::MatrixXd& X, const ArNoiseModel& noise,
                          const SampleLayout& layout);

/// The layout of the prefiltered rows: a row is scored when it and its n predecessors in its
/// segment are (a span not scored spoils the n rows after it).
SampleLayout prefiltered_layout(const SampleLayout& layout, int order);

struct NoiseModelOptions {
  int max_order = 20;  // largest AR order per output (BIC chooses); 0: output error
  int refits = 2;      // rounds of (A_o from the output error, G on the prefiltered data)
};

struct NoiseModelFit {
  // G: each row's fit on its prefiltered data, fit % and residual rms measured again on the
  // data as given (y − ŷ, what an output-error fit reports), the residual tests on ε (the
  // prediction error, which the noise model should leave white). Gain SEs: the prediction-
  // error covariance σ̂²(JᵀJ)⁻¹ on the prefiltered data, widened for the estimated a_j (below)
  // and for what colour is left in ε (widen_row_for_coloured_residual).
  IdentificationResult result;
  std::vector<ArNoiseModel> noise;  // per output; order 0 where BIC chose white noise
  double se_widening = 1.0;         // the largest factor either widening applied to an SE
};

/// The prediction-error fit with a noise model per output (above). Starts from
/// identify(U, Y, …, options) — the output-error fit, its structures chosen as options say —
/// then, per output, `refits` rounds of: fit A_o to the output error, and polish the row on
/// (A_o u, A_o y_o) from the previous row, in its structures. A row whose output error BIC
/// calls white stays the output-error fit, as does one whose prefiltered data identify()
/// refuses (too few scored rows left). The gains' SEs allow for the a_j being estimated
/// too: with X_f the row's gain sensitivities on the prefiltered data and Z the prediction
/// error's sensitivities to the noise parameters (an AR's ∂ε/∂a_j = v(k − j); an ARMA(1,1)'s
/// ∂ε/∂pole = −f(k − 1) and ∂ε/∂zero = g(k − 1), with f = v/(1 − zero·q⁻¹) and
/// g = ε/(1 − zero·q⁻¹)), each gain's variance is (X_fᵀ (I − Z(ZᵀZ)⁻¹Zᵀ) X_f)⁻¹_ii
/// instead of (X_fᵀ X_f)⁻¹_ii, times σ̂² (under feedback u is correlated with past v, and the
/// two parameter sets are not orthogonal as they are in open loop). Throws what identify()
/// throws.
NoiseModelFit identify_with_noise_model(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y,
                                        double T_min, const SampleLayout& layout,
                                        const IdentifyOptions& options = {},
                                        const NoiseModelOptions& noise = {});

}  // namespace excite::host
