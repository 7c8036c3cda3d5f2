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
  double amplitude = 1.0;  // a: the level of steps and PRBS on this input (> 0); used when
                           // the design is sized by input amplitude (Sizing below)
  double min = -1.0;       // lowest allowed deviation (< 0)
  double max = 1.0;        // highest allowed deviation (> 0)
};

/// How big a design is (SPEC §3, host/design/sizing.hpp). static_output is the default and
/// needs G(0): every design sized by the static output it causes, with the thesis's factor
/// c per design. input_amplitude: plain designs move input j by its amplitude a_j and
/// directional designs match the static output RMS of their plain counterpart; a prior
/// without G(0) is always sized so.
enum class Sizing { static_output, input_amplitude };

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
  Sizing sizing = Sizing::static_output;

  int input_count() const { return static_cast<int>(inputs.size()); }
  /// True when designs are sized by static output: asked for, and G(0) known.
  bool sized_by_static_output() const {
    return sizing == Sizing::static_output && gain.size() != 0;
  }
};

/// Throws std::invalid_argument naming the first field that breaks its contract:
/// T > 0, 1…8 inputs, amplitude in (0, min(|min|, max)], min < 0 < max, a finite gain of
/// size outputs × inputs when given.
void validate_inputs(const PriorKnowledge& prior);

/// validate_inputs, and the dynamics the design procedures need: positive time constants
/// with τ_L ≤ τ_H, α > 0, β > 0, step length ≥ 0.
void validate(const PriorKnowledge& prior);

}  // namespace excite::host
