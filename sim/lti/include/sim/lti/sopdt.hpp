// SPDX-License-Identifier: MIT
#pragma once
// The single element of system identification: K e^{−s·Td} / ((1 + s·Tp1)(1 + s·Tp2)),
// time in minutes; Tp = 0 drops that pole (first order, or a delayed static gain).
// Building and discretising neither allocates nor finds roots (the poles are −1/Tp), so
// an identification loop may rebuild it thousands of times.

#include <Eigen/Dense>
#include <cstddef>

#include "sim/lti/discretise.hpp"
#include "sim/lti/element.hpp"

namespace excite::sim {

struct SopdtParameters {
  double gain = 0.0;       // K, output units per input unit
  double delay_min = 0.0;  // Td ≥ 0
  double tau1_min = 0.0;   // Tp1 ≥ 0
  double tau2_min = 0.0;   // Tp2 ≥ 0
};

/// Exact ZOH discretisation at sample time T. Throws std::invalid_argument naming the
/// parameter for non-finite or negative values.
DiscreteTerm discretise_sopdt(const SopdtParameters& p, double sample_time_min);

/// The same element as a continuous Term (for TransferMatrix::set_element).
Term sopdt_term(const SopdtParameters& p);

/// y[k] = H(z) u[k] for k in [0, count) from zero state, delay included. Overwrites y.
void simulate_term(const DiscreteTerm& d, const double* u, double* y, std::size_t count);

/// Convenience: discretise and simulate a column of inputs.
Eigen::VectorXd simulate_sopdt(const SopdtParameters& p, double sample_time_min,
                               const Eigen::VectorXd& u);

}  // namespace excite::sim
