// SPDX-License-Identifier: MIT
#pragma once
// DMC / QDMC (Cutler and Ramaker 1980; Garcia and Morshedi 1986) on a step-response model
// (step_model.hpp). At sample k, with future CVs predicted as ŷ = f + S_u Δu:
//
//   minimise  Σ_{j=1..P} Σ_c w_c (y_sp,c − ŷ_c(k+j))²  +  Σ_{i=0..M−1} Σ_j λ_j Δu_j(k+i)²
//             +  Σ_c ρ ε_c²
//   subject to  |Δu_j(k+i)| ≤ max_move_j,   min_j ≤ u_j(k+i) ≤ max_j          (hard, MVs)
//               lo_c − ε_c ≤ ŷ_c(k+j) ≤ hi_c + ε_c,  ε_c ≥ 0                  (soft, CVs)
//
// and applies the first move. P prediction horizon, M control horizon (moves; u held after
// the M-th), w_c output weights, λ_j move suppression, ρ the slack weight. The CV bounds
// are a zone about the setpoint [y_sp + zone_low, y_sp + zone_high] (a zone CV has no
// tracking term: w_c counts only through its zone) and/or absolute limits
// [limit_low, limit_high]; both soft. The MV box applies to the MV the plant receives,
// u_ctrl + known offset; a box the move limits cannot reach this sample is widened to
// what they can reach (the MV walks back at its largest move).
//
// Free response (the DMC prediction): ŷ(k+j) from every past applied move through S,
// truncated at the settling horizon N, plus the bias y(k) − ŷ(k|k−1) (the measured CV
// minus the model's, held over the horizon: integral action against model error and
// unmeasured disturbances). A known offset's change is a known move in the prediction.
//
// Without any constraint violated the QP's first pass is the unconstrained law
// Δu = (S_uᵀ W_y S_u + W_Δu)⁻¹ S_uᵀ W_y (y_sp − f), first n rows.

#include <Eigen/Dense>

#include <limits>
#include <optional>
#include <vector>

#include "sim/control/active_set_qp.hpp"
#include "sim/control/controller.hpp"
#include "sim/control/step_model.hpp"

namespace excite::sim::control {

inline constexpr double kUnlimited = std::numeric_limits<double>::infinity();

struct MvSettings {
  double min = -kUnlimited;  // MV deviation limits (plant's units)
  double max = kUnlimited;
  double max_move = kUnlimited;   // largest |move| per sample (> 0)
  double move_suppression = 1.0;  // λ_j > 0 (DMC)
};

struct CvSettings {
  double weight = 1.0;    // w_c ≥ 0 (DMC)
  bool zone = false;      // a zone CV: soft bounds about the setpoint, no tracking
  double zone_low = 0.0;  // ≤ zone_high, relative to y_sp
  double zone_high = 0.0;
  double limit_low = -kUnlimited;  // absolute soft limits (deviations)
  double limit_high = kUnlimited;
};

struct DmcSettings {
  int prediction_horizon = 30;  // P ≥ 1 samples
  int control_horizon = 3;      // M, 1 … P moves
  double slack_weight = 1e4;    // ρ > 0
  int max_qp_iterations = 100;  // the real-time cap of the active-set solver
  std::vector<MvSettings> mv;   // n entries
  std::vector<CvSettings> cv;   // p entries
};

class DmcController final : public Controller {
 public:
  /// Throws std::invalid_argument naming the setting (dmc.*, mv[j].*, cv[c].*).
  DmcController(StepModel model, DmcSettings settings);

  int inputs() const noexcept override { return n_; }
  int outputs() const noexcept override { return p_; }
  double sample_time_min() const noexcept override { return model_.sample_time_min; }
  void reset() noexcept override;
  StepReport step(std::span<const double> y, std::span<const double> y_sp,
                  std::span<const double> known_offsets,
                  std::span<double> u_ctrl) noexcept override;
  std::span<const MvStatus> mv_status() const noexcept override { return status_; }

  const StepModel& model() const noexcept { return model_; }
  const DmcSettings& settings() const noexcept { return settings_; }
  /// The dynamic matrix S_u: (P·p) × (M·n), row (j−1)·p + c = CV c at k+j, column i·n + m =
  /// move i of MV m.
  const Eigen::MatrixXd& dynamic_matrix() const noexcept { return Su_; }
  /// The unconstrained law's first move per unit error: n × (P·p).
  const Eigen::MatrixXd& unconstrained_gain() const noexcept { return K_; }
  /// The free response f used by the last step: (P·p), same order as S_u's rows.
  const Eigen::VectorXd& free_response() const noexcept { return f_; }
  int constraint_rows() const noexcept { return static_cast<int>(rows_.size()); }

 private:
  enum class RowKind : unsigned char {
    move_up,
    move_down,
    box_up,
    box_down,
    cv_up,
    cv_down,
    slack
  };
  struct Row {
    RowKind kind;
    int index;  // MV j or CV c
    int step;   // move i, or prediction j (1…P)
  };

  StepModel model_;
  DmcSettings settings_;
  int n_, p_, P_, M_, window_;  // window_ = max(P, N): the prediction kept
  int soft_ = 0;                // CVs with a soft bound, slack variables after the moves
  std::vector<int> slack_of_;   // CV → its slack index, or −1

  Eigen::MatrixXd Su_;
  Eigen::MatrixXd SuT_Q_;  // S_uᵀ W_y, (M·n) × (P·p)
  Eigen::MatrixXd K_;
  std::vector<Row> rows_;
  std::optional<ActiveSetQp> qp_;

  // State.
  Eigen::VectorXd prediction_;  // ŷ(k+j), j = 0 … window_, p each, from past applied moves
  Eigen::VectorXd u_prev_;      // u_ctrl(k−1)
  Eigen::VectorXd offset_prev_;
  std::vector<MvStatus> status_;

  // Work space.
  Eigen::VectorXd f_, e_, g_, b_, x_, applied_move_, cur_;
};

}  // namespace excite::sim::control
