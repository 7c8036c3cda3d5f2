// SPDX-License-Identifier: MIT
#pragma once
// A transfer-function matrix discretised exactly under zero-order hold at sample time T
// (minutes) and simulated in deviation variables from zero initial state. Every term is a
// low-order difference equation (difference_equation.hpp); delays are ring buffers of the
// inputs. Building allocates; step() and reset() never do.

#include <Eigen/Dense>
#include <cstddef>
#include <vector>

#include "sim/lti/discretise.hpp"
#include "sim/lti/transfer_matrix.hpp"

namespace excite::sim {

class DiscretePlant {
 public:
  /// One discrete term: the element from input `in` to output `out` is the sum of its terms.
  struct Section {
    int out;
    int in;
    DiscreteTerm term;
  };

  /// Throws std::invalid_argument for a bad sample time or a term beyond kMaxTermOrder.
  DiscretePlant(const TransferMatrix& g, double sample_time_min);

  int inputs() const { return inputs_; }
  int outputs() const { return outputs_; }
  double sample_time_min() const { return sample_time_min_; }
  const std::vector<Section>& sections() const { return sections_; }

  /// Back to zero state and zero input history (time k = 0).
  void reset();

  /// Sample k: reads u(k) (inputs() values), writes y(k) (outputs() values), advances k.
  /// u(k) reaches y(k) only through direct feedthrough (a term with no delay and
  /// deg num = deg den). Throws std::invalid_argument for a non-finite input.
  void step(const double* u, double* y);

  /// The whole experiment from zero state: U is N × inputs(), returns N × outputs().
  /// Independent of the stepping state. Throws std::invalid_argument for a wrong column
  /// count or non-finite values.
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& u) const;

  /// H(1) of the discrete plant (equals the continuous G(0)).
  Eigen::MatrixXd static_gain() const;

 private:
  int inputs_;
  int outputs_;
  double sample_time_min_;
  std::vector<Section> sections_;
  std::vector<double> state_;  // kMaxCoefficients per section
  // Input history: one power-of-two ring per input at history_offset_[j].
  std::vector<double> history_;
  std::vector<std::size_t> history_offset_;
  std::vector<std::size_t> history_mask_;
  std::size_t tick_ = 0;
};

}  // namespace excite::sim
