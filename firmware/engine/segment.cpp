// SPDX-License-Identifier: MIT
#include "firmware/engine/segment.hpp"

#include <algorithm>

namespace excite::engine {

signal::Status check_segment(const plan::Plan& running, const plan::Plan& next) {
  using signal::Status;
  using signal::StatusCode;
  if (next.recipe.channels != running.recipe.channels) {
    return Status::error(StatusCode::invalid_field,
                         "segment.channels = %u, expected %u (the running plan's)",
                         next.recipe.channels, running.recipe.channels);
  }
  if (next.meta.sample_time_min != running.meta.sample_time_min) {
    return Status::error(StatusCode::invalid_field,
                         "segment.sample_time_min = %g, expected %g (the running plan's)",
                         next.meta.sample_time_min, running.meta.sample_time_min);
  }
  for (std::uint32_t c = 0; c < running.recipe.channels; ++c) {
    const plan::ChannelMeta& a = running.meta.channels[c];
    const plan::ChannelMeta& b = next.meta.channels[c];
    const std::string_view name_a = plan::text_of(a.name);
    const std::string_view name_b = plan::text_of(b.name);
    if (name_a != name_b) {
      return Status::error(StatusCode::invalid_field,
                           "segment.channels[%u].name = \"%.*s\", expected \"%.*s\" (the running "
                           "plan's)",
                           c, static_cast<int>(name_b.size()), name_b.data(),
                           static_cast<int>(name_a.size()), name_a.data());
    }
    if (b.min != a.min) {
      return Status::error(StatusCode::invalid_field,
                           "segment.channels[%u].min = %g, expected %g (the running plan's)", c,
                           b.min, a.min);
    }
    if (b.max != a.max) {
      return Status::error(StatusCode::invalid_field,
                           "segment.channels[%u].max = %g, expected %g (the running plan's)", c,
                           b.max, a.max);
    }
  }
  return {};
}

signal::Status check_segment_table(const EngineConfig& config, std::span<const double> baseline,
                                   signal::ConstTableView table) {
  using signal::Status;
  using signal::StatusCode;
  if (table.data == nullptr || table.channels != config.inputs || baseline.size() < config.inputs) {
    return Status::error(StatusCode::invalid_field, "segment table = %u channels, expected %u",
                         table.channels, config.inputs);
  }
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
                           "input[%u] baseline + segment table = [%g, %g], expected within [%g, "
                           "%g] (baseline %g)",
                           c, baseline[c] + lo, baseline[c] + hi, in.min, in.max, baseline[c]);
    }
  }
  return {};
}

}  // namespace excite::engine
