// SPDX-License-Identifier: MIT
#pragma once
// A start for the output-error fit that sees the whole row at once (SPEC §6, issue 14):
//
//   1. Equation-error (ARX) least squares of the MISO row with one common denominator,
//        A(q) y(k) = Σ_i B_i(q) u_i(k),  A = 1 + a_1 q⁻¹ + … + a_na q^−na,
//        B_i = b_i0 + b_i1 q⁻¹ + … over lags 0 … ⌈max_delay/T⌉ + 2,
//      all inputs together (so no element has to absorb another's response). The order na
//      runs from 0 (FIR) to 2·(inputs), the row's pole count in (6.1.1); the R of one
//      Householder QR of [Φ y] gives the residual of every order at once, and the smallest order
//      the Bayesian information criterion prefers is taken (an order above the row's true one would
//      leave a free common factor in A and B_i).
//   2. Each element's part of the output on these data, z_i = (B_i/A) u_i. When the input
//      lags are rank deficient (a multisine with fewer lines than lags, steps with few
//      edges) B_i is not unique off the excited frequencies, but z_i is. The solve is a
//      truncated SVD of R: directions of rank deficiency, and under noise directions the
//      data do not determine (coefficient standard error above 0.1 ‖y‖), are dropped, so
//      the split of the row between elements does not diverge on noise. The caller fits one (6.1.1)
//      element to each (u_i, z_i) alone — a single-input problem with no other element to absorb —
//      and starts the row's joint fit from those elements.
//
// On data the (6.1.1) structure fits exactly the contributions are exact to rounding (the
// ARX model of a row of second-order elements with a common denominator is exact). Cost:
// linear in the samples N (see ArxBasis).

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "host/identify/segments.hpp"

namespace excite::host {

/// The row's ARX models over the inputs `inputs` (columns of U), the input part shared by
/// every output: Φ_u's QR is computed once (2·N·P_u² flops, P_u = inputs·lags), each output
/// then costs 4·N·P_u·(2n + 1) (its own columns projected) — linear in N.
class ArxBasis {
 public:
  /// Keeps a reference to U (which must outlive the basis). Lags never reach across a
  /// segment's start (the plant at rest before it, as in the simulation); an equation row is
  /// used only when its output and the output lags it needs are scored rows of `layout`.
  /// Unusable (every output gets nullopt) when there are no inputs or fewer than 2·(P + 1)
  /// usable rows.
  ArxBasis(const Eigen::MatrixXd& U, std::vector<int> inputs, double T_min, double max_delay_min,
           const SampleLayout& layout);

  /// The columns z_e (N × inputs.size()) of each element's part of y, from the row's ARX
  /// model; nullopt when the basis is unusable, y is zero, or the model's denominator is
  /// unstable (contributions that diverge). Thread-safe (const).
  std::optional<Eigen::MatrixXd> contributions(const Eigen::VectorXd& y) const;

 private:
  const Eigen::MatrixXd& U_;
  std::vector<int> inputs_;
  Eigen::Index N_;
  std::vector<Segment> segments_;
  Eigen::VectorXd use_;    // 1 for an equation row in the least squares, else 0
  Eigen::Index used_ = 0;  // rows with use_ = 1
  Eigen::Index m_;
  Eigen::Index nb_;                           // lags per input
  Eigen::VectorXd scale_;                     // norms of Φ_u's columns
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;  // of Φ_u, unit-norm columns
  bool usable_ = false;
};

}  // namespace excite::host
