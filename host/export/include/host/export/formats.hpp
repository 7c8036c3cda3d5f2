// SPDX-License-Identifier: MIT
#pragma once
// An identified model written for other tools (`excite export`, host/README.md): the step
// table a DMC-style controller takes, a MATLAB/Octave script, a python-control script and a
// tool-neutral JSON. Every element is (6.1.1) K e^{−s T_d} / ((T_p1 s + 1)(T_p2 s + 1)),
// time in minutes; numerators and denominators are in descending powers of s.

#include <string>
#include <vector>

#include "host/identify/model.hpp"

namespace excite::host {

/// A model with the names of its manipulated (inputs) and controlled (outputs) variables.
struct NamedModel {
  IdentifiedModel model;
  std::vector<std::string> inputs, outputs;
  std::string source;  // where it came from (a file name), for the exported file's header
};

/// Throws std::invalid_argument naming the first element without parameters (status and
/// reason): a controller must not be handed a model with unknown elements.
void require_every_element(const NamedModel& m);

/// CSV: '#' header lines (format, source, sample_time_min, horizon in samples and minutes,
/// what a coefficient is), then `k,t_min,<CV> <- <MV>,…` and rows k = 1 … horizon of the
/// unit-step coefficients s_k = s(kT) (output units per input unit; step_response.hpp).
/// With `bands`, each element's column is followed by two more, `<CV> <- <MV> -2s` and
/// `+2s`: s_k ∓ 2σ_s(kT) from the element's parameter covariance (step_band(); empty cells
/// where σ is not known: a model file without covariance, or a parameter the data did not
/// determine).
std::string step_csv(const NamedModel& m, int horizon_samples, bool bands = false);

/// A MATLAB script that builds `G`, a tf array with InputDelay (per MV, the smallest delay
/// of its column), IODelay (the rest), InputName, OutputName and TimeUnit minutes. Under
/// Octave (control package 3.4 has no delay properties) it builds the same G without the
/// delays, sets the names, and keeps the delays in `input_delay_min` and `io_delay_min`.
std::string matlab_script(const NamedModel& m);

/// A Python script that builds the model with python-control: `G` (control.tf, MIMO, names)
/// without delays, the delays in `DELAYS_MIN`, and `with_pade(order)` for G with each
/// element's delay by a Padé approximation. The model is embedded as the JSON of
/// transfer_json() (`MODEL`), so the script needs nothing but python-control.
std::string python_control_script(const NamedModel& m);

/// {"format":"excite transfer matrix v1","source","time_unit":"min","sample_time_min",
///  "inputs","outputs","elements":[[{"structure","K","Td",… the structure's parameters,
///  "num","den","status","grade","se":{…},"covariance":[[…]…]}…]…]} (rows = outputs; num,
///  den in descending powers of s; se and covariance over the structure's parameters in the
///  order listed, null where unknown). Parameters are written to round-trip exactly.
std::string transfer_json(const NamedModel& m);

/// Reads transfer_json()'s output back. Throws std::invalid_argument naming the field.
NamedModel read_transfer_json(const std::string& text, const std::string& source);

}  // namespace excite::host
