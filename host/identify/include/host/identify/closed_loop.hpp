// SPDX-License-Identifier: MIT
#pragma once
// Identification from closed-loop data (issue 41 §3; /work/shared/CLOSED-LOOP.md, "Identification
// under feedback": Forssell and Ljung, Automatica 35 (1999) 1215; Ljung, System
// Identification, 2nd ed., §13.5; Van den Hof and Schrama, Automatica 29 (1993) 1523).
//
// Under feedback the applied input u is correlated with past disturbances: u = S_i·r −
// C·S·v (S_i the input sensitivity from r to u, v the output disturbance). An output-error
// fit of y on u (the direct method without a noise model) is then biased when v is coloured.
// Two remedies, both used:
//   - the **direct** method with a noise model (noise_model.hpp): the prediction-error fit
//     with a noise model per output is consistent when the noise model describes v;
//   - the **two-stage (projection)** method removes the part of u the disturbance made:
//     stage 1  û = Ŝ_i r: each input regressed by least squares on L Laguerre functions of
//              every r channel (an expansion of the input sensitivity; pole 0: a FIR of L
//              lags); û is uncorrelated with v because r is (excite generates r);
//     stage 2  the same prediction-error fit on (û, y): y = G û + (G (u − û) + v), whose
//              error term is uncorrelated with û, so the estimate is consistent whatever
//              noise model it carries when the loop is linear in r;
//     then     one instrumental-variable step on the gains, with stage 2's sensitivities on
//              û as instruments and the error on the applied u (two_stage_uncertainty.hpp):
//              consistent when the loop is not linear in r either (the MVs' clamps).
// Where the two G(0) disagree beyond 2σ (the two standard errors combined), feedback bias is
// suspected in that element.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "host/identify/identify.hpp"
#include "host/identify/noise_model.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

struct Stage1Fit {
  int lags = 0;           // L: Laguerre functions per r channel (pole 0: lags 0 … L−1)
  double pole = 0.0;      // a: the Laguerre pole
  Eigen::MatrixXd u_hat;  // N × n: the part of u that r explains
  Eigen::VectorXd fit_percent;  // per input, 100·(1 − ‖u − û‖/‖u − ū‖): how much of u is r's
};

/// P_Φ, the orthogonal projection on the span of Φ (N × L·m), whose column l·m + c is r_c
/// through the l-th discrete Laguerre function of `pole` a (rows before 0 taken as 0, at
/// rest): x₀ = √(1 − a²)/(1 − a q⁻¹) r_c, x_l = (q⁻¹ − a)/(1 − a q⁻¹) x_{l−1}. With a = 0
/// this is the FIR of lags 0 … L−1; with a near the loop's slow pole, L functions reach a
/// settling that needs many more lags (Wahlberg, IEEE TAC 36 (1991) 551; Heuberger, Van den
/// Hof and Wahlberg, Modelling and Identification with Rational Orthogonal Basis Functions,
/// 2005). Stage 1's regressors. Built once by a column-pivoting QR (rank-revealing: an r
/// channel that is zero or a copy of another leaves columns it drops); applying it uses
/// orthogonal transformations only. Throws std::invalid_argument (one message form) when R
/// is empty, not finite or zero throughout, lags·m ≥ N / 2, or the pole is outside [0, 1);
/// `lags` 0: default_stage1_lags.
class ReferenceProjection {
 public:
  ReferenceProjection(const Eigen::MatrixXd& R, int lags = 0, double pole = 0.0);
  /// P_Φ X, X with N rows.
  Eigen::MatrixXd operator()(const Eigen::MatrixXd& X) const;
  int lags() const { return lags_; }
  double pole() const { return pole_; }
  Eigen::Index rows() const { return qr_.rows(); }

 private:
  int lags_ = 0;
  double pole_ = 0.0;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

/// The Laguerre pole for stage 1 with `lags` functions per r channel (0: the default).
/// First the loop's time scale: of the grid 0, 0.5, 0.7, 0.8, 0.87, 0.92, 0.95, 0.97, 0.98,
/// the pole a* whose kStage1PoleFunctions functions (at most `lags`) per r channel leave the least
/// of U unexplained (Σ over inputs of ‖u − û‖²/‖u − ū‖²). Then the pole that gives `lags` functions
/// kStage1MemoryFactor times the memory of those few (memory: L·(1 + a)/(1 − a) samples), within
/// [0, a*]: a long record affords lags enough for a FIR (pole 0), and its slow functions would only
/// fit more of the slow disturbance in u, which biases stage 2; a short one reaches the loop's
/// settling through the pole. û stays a function of r alone: the choice reads u, never y. Throws
/// what ReferenceProjection throws, and std::invalid_argument when R's rows are not U's.
inline constexpr int kStage1PoleFunctions = 6;
inline constexpr double kStage1MemoryFactor = 4.0;
double choose_stage1_pole(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags = 0);

/// Stage 1: û = the least-squares projection of each column of U (N × n) on `lags`
/// Laguerre functions (pole `pole`; negative: choose_stage1_pole) of every column of R
/// (N × m), rows before 0 taken as 0 (at rest). `lags` 0: the default, min(200, max(20,
/// N / (8·m))). Throws std::invalid_argument (one message form) when the sizes differ, R is
/// zero throughout, or lags·m ≥ N / 2.
Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags = 0,
                               double pole = -1.0);
/// Stage 1 with P_Φ built (U's rows must be P's).
Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const ReferenceProjection& P);

/// The default stage-1 lags for N rows and m r channels: min(200, max(20, N / (8·m))).
int default_stage1_lags(Eigen::Index rows, Eigen::Index channels);

/// The Laguerre functions per r channel of the instrumental-variable step's own projection
/// (two_stage_uncertainty.hpp): min(200, max(20, N / (32·m))). With stage 1's N/8 regressors
/// the instruments carry more of the controller's answer to the noise, and the step's SEs
/// came out 10–30 % short (many instruments; on alatiqi4x4 part of that was rows that took no
/// step, and 12 functions there changed nothing: host/identify/README.md).
int default_instrument_lags(Eigen::Index rows, Eigen::Index channels);

/// The inputs the instrumental-variable step's instruments are formed on: U projected on
/// min(default_instrument_lags, `stage1_lags`) Laguerre functions of every r channel
/// (0: stage 1's default), their pole chosen by choose_stage1_pole. Throws what
/// ReferenceProjection throws.
Eigen::MatrixXd instrument_inputs(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                                  int stage1_lags = 0);

/// An element whose two G(0) estimates disagree beyond k·σ, σ = √(SE₁² + SE₂²), each SE read
/// from the estimate's reported 95 % interval on the side facing the other estimate (its
/// half-width there over 1.96; model.hpp gain_interval_95): where a projection widens the
/// interval, K ± 1.96·SE alone is short (alatiqi4x4's G23 and G24 under its DMC).
struct GainDisagreement {
  int output = 0;
  int input = 0;
  double two_stage = 0.0, direct = 0.0;
  double sigma = 0.0;  // √(SE_two_stage² + SE_direct²), as above
};

struct ClosedLoopIdentification {
  Stage1Fit stage1;
  double se_widening_two_stage = 1.0;  // NoiseModelFit::se_widening of each
  double se_widening_direct = 1.0;
  // p × n: each two-stage gain's SE after the instrumental-variable step over stage 2's own,
  // and the step ΔK (two_stage_uncertainty.hpp; 1 and 0 where none was taken)
  Eigen::MatrixXd stage1_se_factor;
  Eigen::MatrixXd iv_gain_step;
  IdentificationResult two_stage;               // on (û, y): the estimate
  IdentificationResult direct;                  // on (u, y): the cross-check
  std::vector<ArNoiseModel> noise_two_stage;    // per output, each fit's noise model
  std::vector<ArNoiseModel> noise_direct;       // (order 0: output error on that row)
  std::vector<GainDisagreement> feedback_bias;  // "feedback bias suspected" in these elements
};

/// Elements of two models (same sizes) whose gains differ by more than k·√(SE₁² + SE₂²) (the
/// SEs of the reported intervals, GainDisagreement); elements either model did not estimate,
/// integrators, and gains without a finite interval are skipped.
std::vector<GainDisagreement> gain_disagreements(const IdentifiedModel& two_stage,
                                                 const IdentifiedModel& direct, double k = 2.0);

/// The two-stage estimate alone (the closed-loop adaptive test's and the Monte Carlo
/// experiment's, which need no direct fit beside it).
struct TwoStageFit {
  Stage1Fit stage1;
  NoiseModelFit fit;  // on (û, y), its gains, SEs and gain_uncertainty after the IV step
  // p × n: each gain's SE after the instrumental-variable step over stage 2's own, and the
  // step ΔK (two_stage_uncertainty.hpp; 1 and 0 where none was taken)
  Eigen::MatrixXd stage1_se_factor;
  Eigen::MatrixXd iv_gain_step;
};

/// Each element's structure in `model` (two poles where not estimated), row by row as
/// IdentifyOptions::structures takes them, with every integrator whose rate the
/// instrumental-variable step does not tell from zero (|K| ≤ 1.96·SE) made a first-order lag;
/// empty when there is none. Stage 2 on û can find a rate that the error on the applied u
/// does not hold: alatiqi4x4's G23 = −0.05 under its DMC, in 14 of 100 seeds, whose G(0) was
/// then infinite (host/identify/README.md, "The reported 95 % interval").
std::vector<Structure> lags_for_rates_not_told_from_zero(const IdentifiedModel& model);

/// Stage 1 (û = P_Φ U; `stage1_lags` and `stage1_pole` as in project_on_reference), then the
/// prediction-error fit with a noise model per output on (û, Y) (noise_model.hpp), each
/// row's gains finished by one instrumental-variable step with their SEs
/// (instrument_step_in_row), and G(0)'s uncertainty (gain_uncertainty) formed again from them.
/// Where the step leaves an integrator's rate within 1.96 SE of zero, stage 2 and the step are
/// made again with the structures of lags_for_rates_not_told_from_zero (not when `options`
/// forces structures).
/// Throws what identify() and stage 1 throw, and std::invalid_argument when R's rows are not U's.
TwoStageFit identify_two_stage(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                               const Eigen::MatrixXd& Y, double T_min, const SampleLayout& layout,
                               const IdentifyOptions& options = {}, int stage1_lags = 0,
                               const NoiseModelOptions& noise = {}, double stage1_pole = -1.0);

/// Both methods on one closed-loop run: U applied inputs, R the test signal r (N × m), Y.
/// `stage1_lags`, `stage1_pole` as in project_on_reference. Each is the prediction-error fit with
/// a noise model per output (noise_model.hpp; `noise.max_order` 0: output error): on (û, y) the
/// two-stage estimate, on (u, y) the direct one — consistent in closed loop when the noise model
/// describes the disturbance (the output-error direct fit is not, with a coloured one). The gain
/// standard errors allow for the estimated noise model and for the colour left in the residual, and
/// the two-stage ones come from the instrumental-variable step (identify_two_stage). Throws what
/// identify() and stage 1 throw.
ClosedLoopIdentification identify_closed_loop(
    const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, const Eigen::MatrixXd& Y, double T_min,
    const SampleLayout& layout, const IdentifyOptions& options = {}, int stage1_lags = 0,
    const NoiseModelOptions& noise = {}, double stage1_pole = -1.0);

}  // namespace excite::host
