// SPDX-License-Identifier: MIT
#pragma once
// Initialisation of the output-error fit (finding the basin): a bank of unit-gain element
// responses on a grid of (delay, time constant, shape) per input, shared by all outputs,
// and a coordinate search that picks one grid response per element.

#include <Eigen/Dense>
#include <vector>

#include "host/identify/element.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

struct GridSpec {
  double max_delay_min = 20.0;
  double max_time_constant_min = 1000.0;
};

class ResponseBank {
 public:
  /// Simulates every grid element (gain 1) for each input in `inputs` (columns of U), each
  /// segment of `layout` from rest; rows outside the cost are zero in every response (so
  /// choose() and choose_one() must be given outputs with those rows zero too).
  /// Grid: delays 0 … max_delay in max(T, max_delay/10) steps; T_p1 geometric by 2 from
  /// T/2 to min(max_time_constant, N·T/8); T_p2 = T_p1/4.
  ResponseBank(const Eigen::MatrixXd& U, const std::vector<int>& inputs, double T_min,
               const GridSpec& grid, const SampleLayout& layout);

  /// Grid elements (gain 1), same for every input.
  const std::vector<ElementModel>& grid() const { return grid_; }

  /// For output y: per input of the bank, the index of the chosen grid element and the
  /// jointly least-squares gains. Sweeps over the inputs until no choice changes (≤ 6).
  struct Choice {
    std::vector<int> grid_index;  // per bank input
    Eigen::VectorXd gain;         // per bank input
  };
  Choice choose(const Eigen::VectorXd& y) const;

  /// The grid elements `choice` names, with its gains: one start element per bank input.
  std::vector<ElementModel> elements(const Choice& choice) const;

  /// As choose(), with the bank inputs of `group` sharing one grid element (their gains
  /// free), chosen after each sweep of the others (choose() is the empty group): the start for
  /// inputs that move together (issue 43). Their output's valley along the split of their gains has
  /// local optima where each element's own dynamics bend to fit the small own parts of the inputs;
  /// with the dynamics alike the split is the least-squares one of the group's responses, and on
  /// Wood–Berry with u2 = u1 ± 1.4 % the fit from there reached the truth's basin in 5 of 6 rows
  /// where choose()'s did in 1.
  Choice choose_shared(const Eigen::VectorXd& y, const std::vector<Eigen::Index>& group) const;

  /// As choose(), with bank inputs a and b chosen together: every pair of grid elements,
  /// each with its least-squares gains on the residual of the other inputs (one product of
  /// the two banks). For two inputs that move together, whose own dynamics differ (Wood–Berry
  /// y2: delays 7 and 3 min) so that choose_shared's common element misleads the split.
  Choice choose_pair(const Eigen::VectorXd& y, Eigen::Index a, Eigen::Index b) const;

  /// For the part z of an output due to bank input e alone: the grid element (index) with
  /// the best 1-D least-squares gain (returned in `gain`).
  int choose_one(Eigen::Index e, const Eigen::VectorXd& z, double& gain) const;

  /// As choose_one(), for the own part of bank input b: b less beta times bank input a
  /// (the responses are linear in the input).
  int choose_own_part(Eigen::Index b, Eigen::Index a, double beta, const Eigen::VectorXd& z,
                      double& gain) const;

 private:
  // The grid element of bank input i whose response best fits r by its 1-D least-squares
  // gain (the largest (zᵀr)²/‖z‖²), with its zᵀr and ‖z‖² (the gain is their ratio).
  struct Best {
    Eigen::Index index;
    float projection;
    float norm2;
  };
  Best best_response(Eigen::Index i, const Eigen::VectorXd& r) const;

  std::vector<ElementModel> grid_;
  std::vector<Eigen::MatrixXf> responses_;  // per input: N × grid, single precision
  std::vector<Eigen::VectorXf> norms2_;     // per input: ‖response‖² per grid element
};

}  // namespace excite::host
