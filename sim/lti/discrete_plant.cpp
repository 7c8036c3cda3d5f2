// SPDX-License-Identifier: MIT
#include "sim/lti/discrete_plant.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/lti/difference_equation.hpp"

namespace excite::sim {

DiscretePlant::DiscretePlant(const TransferMatrix& g, double sample_time_min)
    : inputs_(g.inputs()), outputs_(g.outputs()), sample_time_min_(sample_time_min) {
  for (int i = 0; i < outputs_; ++i) {
    for (int j = 0; j < inputs_; ++j) {
      for (const Term& t : g.element(i, j).terms()) {
        try {
          sections_.push_back({i, j, discretise_zoh(t, sample_time_min)});
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument("G " + g.describe_position(i, j) + " \"" +
                                      g.element(i, j).text() + "\": " + e.what());
        }
      }
    }
  }
  state_.assign(sections_.size() * kMaxCoefficients, 0.0);
  std::vector<int> longest(static_cast<std::size_t>(inputs_), 0);
  for (const Section& s : sections_) {
    int& l = longest[static_cast<std::size_t>(s.in)];
    l = std::max(l, s.term.delay_samples);
  }
  std::size_t offset = 0;
  for (int l : longest) {
    std::size_t capacity = 1;
    while (capacity < static_cast<std::size_t>(l) + 1) capacity <<= 1U;
    history_offset_.push_back(offset);
    history_mask_.push_back(capacity - 1);
    offset += capacity;
  }
  history_.assign(offset, 0.0);
}

void DiscretePlant::reset() {
  std::fill(state_.begin(), state_.end(), 0.0);
  std::fill(history_.begin(), history_.end(), 0.0);
  tick_ = 0;
}

void DiscretePlant::step(const double* u, double* y) {
  for (int j = 0; j < inputs_; ++j) {
    if (!std::isfinite(u[j])) {
      throw std::invalid_argument("input " + std::to_string(j + 1) + " at sample " +
                                  std::to_string(tick_) + " is " + std::to_string(u[j]) +
                                  ", expected a finite value");
    }
  }
  for (int j = 0; j < inputs_; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    history_[history_offset_[uj] + (tick_ & history_mask_[uj])] = u[j];
  }
  std::fill(y, y + outputs_, 0.0);
  double* state = state_.data();
  for (const Section& s : sections_) {
    const auto in = static_cast<std::size_t>(s.in);
    const std::size_t slot =
        (tick_ - static_cast<std::size_t>(s.term.delay_samples)) & history_mask_[in];
    y[s.out] += tdf2_step(s.term, state, history_[history_offset_[in] + slot]);
    state += kMaxCoefficients;
  }
  ++tick_;
}

Eigen::MatrixXd DiscretePlant::simulate(const Eigen::MatrixXd& u) const {
  if (u.cols() != inputs_) {
    throw std::invalid_argument("input matrix U has " + std::to_string(u.cols()) +
                                " columns, expected " + std::to_string(inputs_) +
                                " (one per input, N rows of samples)");
  }
  if (!u.allFinite()) {
    Eigen::Index r = 0;
    Eigen::Index c = 0;
    (!u.array().isFinite()).cast<int>().maxCoeff(&r, &c);
    throw std::invalid_argument("input matrix U(" + std::to_string(r) + ", " + std::to_string(c) +
                                ") is " + std::to_string(u(r, c)) + ", expected a finite value");
  }
  const auto n = static_cast<std::size_t>(u.rows());
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(u.rows(), outputs_);
  // Sample-major: at each sample all terms advance one step. Their recurrences are
  // independent, so the processor overlaps them (term-major would wait on one chain).
  std::vector<double> state(sections_.size() * kMaxCoefficients, 0.0);
  const double* u_data = u.data();
  double* y_data = y.data();
  const auto rows = static_cast<std::size_t>(u.rows());
  for (std::size_t k = 0; k < n; ++k) {
    double* st = state.data();
    for (const Section& s : sections_) {
      const auto delay = static_cast<std::size_t>(s.term.delay_samples);
      if (k >= delay) {
        const double x = u_data[static_cast<std::size_t>(s.in) * rows + k - delay];
        y_data[static_cast<std::size_t>(s.out) * rows + k] += tdf2_step(s.term, st, x);
      }
      st += kMaxCoefficients;
    }
  }
  return y;
}

Eigen::MatrixXd DiscretePlant::static_gain() const {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(outputs_, inputs_);
  for (const Section& s : sections_) g(s.out, s.in) += s.term.static_gain();
  return g;
}

}  // namespace excite::sim
