// SPDX-License-Identifier: MIT
#pragma once
// What the engineer knows of a plant before the test (SPEC §1, §3; thesis Table 4.1).
// Time in minutes; amplitudes and limits in each input's engineering unit, as deviations
// from the operating point.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace excite::host {

struct InputSpec {
  std::string name;
  double amplitude = 1.0;  // a: the level of steps and PRBS on this input (> 0)
  double min = -1.0;       // lowest allowed deviation (< 0)
  double max = 1.0;        // highest allowed deviation (> 0)
};

struct PriorKnowledge {
  std::string plant;              // provenance: library plant name or the spec file
  double sample_time_min = 1.0;   // T
  double tau_low_min = 0.0;       // τ_L, low dominating time constant
  double tau_high_min = 0.0;      // τ_H, high dominating time constant
  double alpha = 2.0;             // α: open-loop / desired closed-loop time constant
  double beta = 3.0;              // β: settling time in units of τ_H
  double step_length_min = 0.0;   // each +a and −a step; 0 → derived from the length
  std::vector<InputSpec> inputs;  // one per plant input
  Eigen::MatrixXd gain;           // G(0), outputs × inputs; empty when unknown

  int input_count() const { return static_cast<int>(inputs.size()); }
};

/// Throws std::invalid_argument naming the first field that breaks its contract:
/// T > 0, 1…8 inputs, amplitude in (0, min(|min|, max)], min < 0 < max, a finite gain of
/// size outputs × inputs when given.
void validate_inputs(const PriorKnowledge& prior);

/// validate_inputs, and the dynamics the design procedures need: positive time constants
/// with τ_L ≤ τ_H, α > 0, β > 0, step length ≥ 0.
void validate(const PriorKnowledge& prior);

}  // namespace excite::host
