// SPDX-License-Identifier: MIT
#pragma once
// How well the gain directions of an identified G(0) are known (SPEC §3, §6: singular
// values and directions of G(0) = W Σ Vᵀ, (5.2.1)), from the gains' covariance:
//  - σ_i ± SE(σ_i);
//  - the angle uncertainty of every input direction v_i and output direction w_i: the RMS
//    angle between the estimated and a perturbed direction, √E‖δv_i‖² (radians → degrees);
//  - every principal minor of a square G(0) with its SE, and whether a gain error within
//    its 95 % interval can flip its sign. The signs of the principal minors decide integral
//    controllability (a controller built on the model, with integral action, stays stable
//    for the plant only when the model's minors have the plant's signs: Koung & MacGregor
//    1993, Morari 1985); an ill-conditioned plant's det G(0) is the minor most at risk.
// All by first-order propagation (linearisation): each function f of G(0) (σ_i, v_i, w_i,
// a minor) is differentiated by central differences of the SVD or determinant in each
// gain (singular vectors sign-aligned), and Var f = ∇fᵀ Σ_K ∇f with Σ_K block-diagonal: one
// block per output row (IdentifiedModel::gain_covariance; rows are fitted apart and their
// noises are independent). Linearisation holds while the errors are small against the gaps
// between singular values; tests/unit/host_identify checks it against sampling.

#include <Eigen/Dense>
#include <vector>

namespace excite::host {

struct PrincipalMinor {
  std::vector<int> rows;  // the same indices of rows and columns, 0-based, ascending
  double value = 0.0;
  double std_error = 0.0;
  bool sign_uncertain = false;  // |value| < 1.96 · std_error
};

struct GainUncertainty {
  Eigen::VectorXd singular_values;               // σ_1 ≥ … ≥ σ_r of G(0)
  Eigen::VectorXd singular_value_se;             // SE(σ_i)
  Eigen::VectorXd input_angle_se_deg;            // per direction i: √E‖δv_i‖², degrees
  Eigen::VectorXd output_angle_se_deg;           // per direction i: √E‖δw_i‖², degrees
  std::vector<PrincipalMinor> principal_minors;  // square G(0) only; by size, then index
  int sign_uncertain_minors = 0;
};

/// From G (p × n) and the per-output gain covariances (p matrices of n × n). Throws
/// std::invalid_argument when sizes disagree or G or a covariance has a NaN entry.
GainUncertainty gain_uncertainty(const Eigen::MatrixXd& G,
                                 const std::vector<Eigen::MatrixXd>& row_covariance);

}  // namespace excite::host
