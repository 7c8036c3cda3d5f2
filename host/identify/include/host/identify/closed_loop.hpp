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
//     with an AR noise model per output is consistent when the noise model describes v;
//   - the **two-stage (projection)** method removes the part of u the disturbance made:
//     stage 1  û = Ŝ_i r: each input regressed by least squares on the lags 0 … L−1 of every
//              r channel (a long FIR of the input sensitivity); û is uncorrelated with v
//              because r is (excite generates r);
//     stage 2  the same prediction-error fit on (û, y): y = G û + (G (u − û) + v), whose
//              error term is uncorrelated with û, so the estimate is consistent whatever
//              noise model it carries (it needs the loop linear in r).
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
  int lags = 0;           // L: FIR taps per r channel (lags 0 … L−1)
  Eigen::MatrixXd u_hat;  // N × n: the part of u that r explains
  Eigen::VectorXd fit_percent;  // per input, 100·(1 − ‖u − û‖/‖u − ū‖): how much of u is r's
};

/// P_Φ, the orthogonal projection on the span of Φ (N × L·m), whose column l·m + c is
/// r_c(k − l), rows before 0 taken as 0 (at rest): stage 1's regressors. Built once by a
/// column-pivoting QR (rank-revealing: an r channel that is zero or a copy of another leaves
/// columns it drops); applying it uses orthogonal transformations only. Throws
/// std::invalid_argument (one message form) when R is empty, not finite or zero throughout,
/// or lags·m ≥ N / 2; `lags` 0: default_stage1_lags.
class ReferenceProjection {
 public:
  ReferenceProjection(const Eigen::MatrixXd& R, int lags = 0);
  /// P_Φ X, X with N rows.
  Eigen::MatrixXd operator()(const Eigen::MatrixXd& X) const;
  int lags() const { return lags_; }
  Eigen::Index rows() const { return qr_.rows(); }

 private:
  int lags_ = 0;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

/// Stage 1: û = the least-squares FIR projection of each column of U (N × n) on the lags
/// 0 … lags−1 of every column of R (N × m), rows before 0 taken as 0 (at rest). `lags` 0:
/// the default, min(200, max(20, N / (8·m))) — long enough for the closed loop's settling
/// at a few parameters per 8 rows. Throws std::invalid_argument (one message form) when the
/// sizes differ, R is zero throughout, or lags·m ≥ N / 2.
Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags = 0);
/// Stage 1 with P_Φ built (U's rows must be P's).
Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const ReferenceProjection& P);

/// The default stage-1 lags for N rows and m r channels: min(200, max(20, N / (8·m))).
int default_stage1_lags(Eigen::Index rows, Eigen::Index channels);

/// An element whose two G(0) estimates disagree beyond k·σ, σ = √(SE₁² + SE₂²).
struct GainDisagreement {
  int output = 0;
  int input = 0;
  double two_stage = 0.0, direct = 0.0;
  double sigma = 0.0;  // √(SE_two_stage² + SE_direct²)
};

struct ClosedLoopIdentification {
  Stage1Fit stage1;
  double se_widening_two_stage = 1.0;  // NoiseModelFit::se_widening of each
  double se_widening_direct = 1.0;
  // p × n: the factor counting stage 1's error put on each two-stage gain SE (≥ 1;
  // two_stage_uncertainty.hpp; 1 where none was applied)
  Eigen::MatrixXd stage1_se_factor;
  IdentificationResult two_stage;               // on (û, y): the estimate
  IdentificationResult direct;                  // on (u, y): the cross-check
  std::vector<ArNoiseModel> noise_two_stage;    // per output, each fit's AR noise model
  std::vector<ArNoiseModel> noise_direct;       // (order 0: output error on that row)
  std::vector<GainDisagreement> feedback_bias;  // "feedback bias suspected" in these elements
};

/// Elements of two models (same sizes) whose gains differ by more than k·√(SE₁² + SE₂²);
/// elements either model did not estimate, or without a standard error, are skipped.
std::vector<GainDisagreement> gain_disagreements(const IdentifiedModel& two_stage,
                                                 const IdentifiedModel& direct, double k = 2.0);

/// The two-stage estimate alone (the closed-loop adaptive test's and the Monte Carlo
/// experiment's, which need no direct fit beside it).
struct TwoStageFit {
  Stage1Fit stage1;
  NoiseModelFit fit;  // on (û, y); its gain SEs and gain_uncertainty count stage 1's error
  // p × n: the factor counting stage 1's error put on each gain SE (≥ 1;
  // two_stage_uncertainty.hpp; 1 where none was applied)
  Eigen::MatrixXd stage1_se_factor;
};

/// Stage 1 (û = P_Φ U, P_Φ on R's lags; `stage1_lags` as in project_on_reference), then the
/// prediction-error fit with an AR noise model per output on (û, Y) (noise_model.hpp), each
/// row's gain SEs widened for stage 1's error (count_stage1_in_row) and G(0)'s uncertainty
/// (gain_uncertainty) formed again from them. Throws what identify() and stage 1 throw, and
/// std::invalid_argument when R's rows are not U's.
TwoStageFit identify_two_stage(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                               const Eigen::MatrixXd& Y, double T_min, const SampleLayout& layout,
                               const IdentifyOptions& options = {}, int stage1_lags = 0,
                               const NoiseModelOptions& noise = {});

/// Both methods on one closed-loop run: U applied inputs, R the test signal r (N × m), Y.
/// `stage1_lags` as in project_on_reference. Each is the prediction-error fit with an AR
/// noise model per output (noise_model.hpp; `noise.max_order` 0: output error): on (û, y)
/// the two-stage estimate, on (u, y) the direct one — consistent in closed loop when the
/// noise model describes the disturbance (the output-error direct fit is not, with a
/// coloured one). The gain standard errors allow for the estimated noise model and for the
/// colour left in the residual, and the two-stage ones for stage 1's error in û
/// (identify_two_stage). Throws what identify() and stage 1 throw.
ClosedLoopIdentification identify_closed_loop(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                                              const Eigen::MatrixXd& Y, double T_min,
                                              const SampleLayout& layout,
                                              const IdentifyOptions& options = {},
                                              int stage1_lags = 0,
                                              const NoiseModelOptions& noise = {});

}  // namespace excite::host
