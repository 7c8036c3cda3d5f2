// SPDX-License-Identifier: MIT
#include "firmware/engine/table_checks.hpp"

#include <algorithm>

namespace excite::engine {

using signal::Status;
using signal::StatusCode;

Status check_table_shape(signal::ConstTableView table, std::uint32_t inputs,
                         const char* what) noexcept {
  if (table.data == nullptr || table.channels != inputs || table.samples == 0) {
    return Status::error(StatusCode::invalid_field,
                         "%s = %u channels x %u samples, expected %u channels (the "
                         "configuration's setpoints) and at least 1 sample",
                         what, table.channels, table.samples, inputs);
  }
  return {};
}

Status check_table_range(const EngineConfig& config, std::span<const double> baseline,
                         signal::ConstTableView table, const char* what) noexcept {
  for (std::uint32_t c = 0; c < config.inputs; ++c) {
    const InputLimits& in = config.input[c];
    double lo = 0.0;
    double hi = 0.0;
    for (std::uint32_t k = 0; k < table.samples; ++k) {
      lo = std::min(lo, table.at(k, c));
      hi = std::max(hi, table.at(k, c));
    }
    if (baseline[c] + lo < in.min || baseline[c] + hi > in.max) {
      return Status::error(StatusCode::limit_violated,
                           "input[%u] baseline + %s = [%g, %g], expected within [%g, %g] "
                           "(baseline %g)",
                           c, what, baseline[c] + lo, baseline[c] + hi, in.min, in.max,
                           baseline[c]);
    }
  }
  return {};
}

}  // namespace excite::engine
