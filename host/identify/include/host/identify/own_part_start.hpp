// SPDX-License-Identifier: MIT
#pragma once
// Starts for a row whose two inputs move together (issue 43): one element of the pair found
// from its input's own part, the other from what that element leaves.
//
// With u_b ≈ β·u_a the output determines G_a + β·G_b well and the split between them only
// through u_b's small own part u_b − β·u_a and the elements' different dynamics. In the
// inputs as moved the split is near singular: the row's ARX model drops it (its truncated
// SVD), the grid's pair start chooses it from responses nearly alike, and the joint fits
// from those starts end in a basin 30–500 σ̂² above the refit from the truth (Wood–Berry,
// u2 = u1 at a 1 % own part: row y2 in 25 of 30 seeds, row y1 in 5, row y2 at or near the
// same wrong gains seed after seed). In the inputs (u_a, u_b − β·u_a) the same row is well
// conditioned: G_b is the only response to the own part, which moves independently of u_a.
// So the row's ARX model on those inputs gives G_b's contribution, one element is fitted to
// it alone, and G_a is then fitted alone to what G_b on the whole u_b leaves. Both
// orientations are tried (b's own part, a's own part): which input's own part carries its
// element better is the data's to say.

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "host/identify/arx_start.hpp"
#include "host/identify/gain_profile.hpp"
#include "host/identify/response_bank.hpp"

namespace excite::host {

class OwnPartStarts {
 public:
  /// For inputs a and b (positions in `inputs`, the columns of U the row's elements take) that
  /// move together: β of each on the other over the scored rows of `layout`, and the ARX
  /// bases on the inputs with one of them replaced by its own part (built once, on first use
  /// by starts(), shared by every output's row). Keeps references to nothing passed.
  OwnPartStarts(const Eigen::MatrixXd& U, const std::vector<int>& inputs, std::size_t a,
                std::size_t b, double T_min, double max_delay_min, const SampleLayout& layout);
  ~OwnPartStarts();
  OwnPartStarts(const OwnPartStarts&) = delete;
  OwnPartStarts& operator=(const OwnPartStarts&) = delete;

  /// The two starts for `row` (row.y: the output less its trend, as the other starts see
  /// it; row.trend unused): `from` (the other elements' start) with the pair's elements
  /// found from b's own part, then from a's. A start whose ARX model cannot split the
  /// output is `from` unchanged. `bank` is the row's response bank over `inputs`.
  std::vector<std::vector<ElementModel>> starts(const RowProblem& row, const ResponseBank& bank,
                                                const std::vector<ElementModel>& from) const;

  /// `from` with the pair's dynamics exchanged: a's element takes b's dynamics with gain
  /// β·K_b, b's takes a's with K_a/β, so that G_a + β·G_b, what the data determine, stays.
  /// The other side of a split that rests on the elements' dynamics (two elements alike but
  /// for their delays leave an optimum with the delays exchanged).
  std::vector<ElementModel> exchanged(std::vector<ElementModel> from) const;

  /// Starts along the combination (four): `from` with both of the pair's elements in the
  /// dynamics of the one whose part of the output, |K|·‖u‖, is larger, their gains the least-
  /// squares split of what the other elements leave of row.y, then that split's K_a + β·K_b
  /// given a quarter, a half and three quarters to a. For an end where one element carries
  /// the combination and the other bends to fit the own part (alatiqi4x4's row y3, two
  /// elements alike but for 6 min of delay, at a 1 % own part: an optimum 1–9 σ̂² above the
  /// refit from the truth in 8 of 30 seeds), the split is then the fit's to find again.
  std::vector<std::vector<ElementModel>> shared(const RowProblem& row,
                                                std::vector<ElementModel> from) const;

 private:
  struct Side;  // one orientation: the input whose own part is taken, its β, its ARX basis
  std::vector<ElementModel> start(const Side& side, const RowProblem& row, const ResponseBank& bank,
                                  std::vector<ElementModel> from) const;
  std::unique_ptr<const Side> sides_[2];
};

}  // namespace excite::host
