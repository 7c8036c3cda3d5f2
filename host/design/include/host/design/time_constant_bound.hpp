// SPDX-License-Identifier: MIT
#pragma once
// The upper bound of the identified time constants (SPEC §6: β·τ_H), as `excite identify`
// and `excite crossval` take it, first found of:
//   an explicit bound (--max-time-constant MIN; 0: the run's length, accepted on purpose);
//   τ_H given × (β given, else the first run log's β, else 3);
//   the run logs' own `# tau_high_min:` × `# beta:` header (the plan's design, carried by
//   every producer: firmware/runlog/README.md) — the largest when runs differ;
//   the case study of the run log's plant name (logs written before the header existed);
// otherwise no bound is known and it refuses, naming the options: a bound of the run's length
// lets an element absorb another's misfit with a slow lag and a large gain (σ₄ of alatiqi4x4
// came out 3.9× too large so).

#include <string>
#include <utility>
#include <vector>

namespace excite::host {

/// What the user gave; each "not given" by its default.
struct TimeConstantBoundOptions {
  double max_time_constant_min = -1.0;  // < 0: not given
  double tau_high_min = 0.0;            // 0: not given
  double beta = 0.0;                    // 0: not given (the run log's β, else 3)
};

/// What a run says of its design: its plant's name and its header's time scales (0: absent).
struct RunTimeScales {
  std::string path;
  std::string plant;
  double tau_high_min = 0.0;
  double beta = 0.0;
};

/// The bound in minutes (0: identify()'s run length, only when asked for with
/// --max-time-constant 0) and where it came from, in words. Throws std::invalid_argument
/// naming the options when no bound is known.
std::pair<double, std::string> time_constant_bound(const TimeConstantBoundOptions& o,
                                                   const std::vector<RunTimeScales>& runs);

}  // namespace excite::host
