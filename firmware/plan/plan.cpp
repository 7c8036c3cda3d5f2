// SPDX-License-Identifier: MIT
#include "firmware/plan/plan.hpp"

#include <cmath>

#include "firmware/signal/validate.hpp"

namespace excite::plan {
namespace {

template <std::size_t N>
bool terminated(const Text<N>& text) {
  for (const char ch : text) {
    if (ch == '\0') return true;
  }
  return false;
}

}  // namespace

const char* to_text(Excitation e) noexcept {
  switch (e) {
    case Excitation::open_loop:
      return "open_loop";
    case Excitation::setpoint:
      return "setpoint";
    case Excitation::mv:
      return "mv";
  }
  return "unknown";
}

Status validate(const Plan& plan) {
  if (Status s = signal::validate(plan.recipe); !s) return s;
  const Metadata& meta = plan.meta;
  if (meta.format_version == 0 || meta.format_version > kNewestFormatVersion) {
    return Status::error(StatusCode::unsupported_version,
                         "meta.format_version = %u, expected 1…%u (the versions this build reads)",
                         unsigned{meta.format_version}, unsigned{kNewestFormatVersion});
  }
  if (static_cast<std::uint8_t>(meta.excitation) > static_cast<std::uint8_t>(Excitation::mv)) {
    return Status::error(StatusCode::invalid_field,
                         "meta.excitation = %u, expected 0 (open loop), 1 (setpoint) or 2 (mv)",
                         unsigned{static_cast<std::uint8_t>(meta.excitation)});
  }
  if (!terminated(meta.design_name)) {
    return Status::error(StatusCode::invalid_field,
                         "meta.design_name has no terminating NUL, expected ≤ %zu bytes",
                         kNameCapacity - 1);
  }
  if (!terminated(meta.provenance)) {
    return Status::error(StatusCode::invalid_field,
                         "meta.provenance has no terminating NUL, expected ≤ %zu bytes",
                         kProvenanceCapacity - 1);
  }
  if (!(std::isfinite(meta.sample_time_min) && meta.sample_time_min > 0.0)) {
    return Status::error(StatusCode::invalid_field,
                         "meta.sample_time_min = %g, expected a finite number > 0",
                         meta.sample_time_min);
  }
  const struct {
    const char* name;
    double value;
  } time_scales[] = {{"tau_high_min", meta.tau_high_min},
                     {"beta", meta.beta},
                     {"switch_time_min", meta.switch_time_min}};
  for (const auto& t : time_scales) {
    if (!(std::isfinite(t.value) && t.value >= 0.0)) {
      return Status::error(StatusCode::invalid_field,
                           "meta.%s = %g, expected a finite number ≥ 0 (0: not known)", t.name,
                           t.value);
    }
  }
  for (std::uint32_t c = 0; c < plan.recipe.channels; ++c) {
    const ChannelMeta& ch = meta.channels[c];
    if (!terminated(ch.name)) {
      return Status::error(StatusCode::invalid_field,
                           "meta.channels[%u].name has no terminating NUL, expected ≤ %zu bytes", c,
                           kNameCapacity - 1);
    }
    if (!std::isfinite(ch.min)) {
      return Status::error(StatusCode::invalid_field,
                           "meta.channels[%u].min = %g, expected a finite number", c, ch.min);
    }
    if (!std::isfinite(ch.max)) {
      return Status::error(StatusCode::invalid_field,
                           "meta.channels[%u].max = %g, expected a finite number", c, ch.max);
    }
    if (ch.min > ch.max) {
      return Status::error(StatusCode::invalid_field,
                           "meta.channels[%u].min = %g, expected ≤ max = %g", c, ch.min, ch.max);
    }
  }
  return {};
}

}  // namespace excite::plan
