// SPDX-License-Identifier: MIT
#include "firmware/engine/segment.hpp"

#include "firmware/engine/table_checks.hpp"

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
  if (baseline.size() < config.inputs) {
    return signal::Status::error(signal::StatusCode::invalid_field,
                                 "baseline = %zu values, expected %u (the setpoints)",
                                 baseline.size(), config.inputs);
  }
  if (auto s = check_table_shape(table, config.inputs, "segment table"); !s) return s;
  return check_table_range(config, baseline, table, "segment table");
}

}  // namespace excite::engine
