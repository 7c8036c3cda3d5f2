// SPDX-License-Identifier: MIT
#pragma once
// An identification as `excite identify` prints it on the terminal: per output its fit, the
// residual whiteness test, the inputs that moved together, a table of every element's
// structure, parameters ± SE, grade and status, and what kept an element from grade A; then
// the identified G(0)'s singular values, condition number and uncertainty (σ_i ± SE, the
// direction angles' SE, the principal minors whose sign is uncertain). Channels are named
// as in the run log.

#include <ostream>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/identify/identify.hpp"

namespace excite::host {

void print_identification(std::ostream& out, const IdentificationResult& r,
                          const runlog::RunLog& log);

/// One line: each output's AR noise-model order (noise_model.hpp), by the log's names.
void print_noise_orders(std::ostream& out, const std::vector<ArNoiseModel>& noise,
                        const runlog::RunLog& log);

/// A closed-loop run's cross-check: the other method's G(0) ± SE (the two-stage one when
/// `direct` is the model written, else the direct fit's) and the elements where the two
/// disagree by more than 2σ (feedback bias suspected).
void print_closed_loop(std::ostream& out, const ClosedLoopIdentification& id,
                       const runlog::RunLog& log, bool direct);

/// "OUTPUT<-INPUT" by the run log's channel names.
std::string element_name(const runlog::RunLog& log, int o, int i);

}  // namespace excite::host
