// SPDX-License-Identifier: MIT
#include "firmware/signal/validate.hpp"

#include <cmath>
#include <cstdarg>

#include "firmware/signal/mseq.hpp"
#include "firmware/signal/trig.hpp"

namespace excite::signal {
namespace {

using U64 = unsigned long long;  // for printf's %llu

__attribute__((format(printf, 1, 2))) Status invalid(const char* format, ...) {
  va_list args;
  va_start(args, format);
  Status status = Status::error_v(StatusCode::invalid_field, format, args);
  va_end(args);
  return status;
}

Status check_steps(std::uint32_t i, const StepSource& steps) {
  if (steps.segment_count > kMaxSegments) {
    return Status::error(StatusCode::capacity_exceeded,
                         "sources[%u].steps.segment_count = %u, expected ≤ %u", i,
                         steps.segment_count, kMaxSegments);
  }
  for (std::uint32_t s = 0; s < steps.segment_count; ++s) {
    if (!std::isfinite(steps.segments[s].level)) {
      return invalid("sources[%u].steps.segments[%u].level = %g, expected a finite number", i, s,
                     steps.segments[s].level);
    }
  }
  return {};
}

Status check_prbs(std::uint32_t i, const PrbsSource& prbs) {
  if (!valid_register_length(prbs.register_length)) {
    return invalid("sources[%u].prbs.register_length = %u, expected %d…%d", i,
                   unsigned{prbs.register_length}, kMinRegisterLength, kMaxRegisterLength);
  }
  if (!std::isfinite(prbs.amplitude)) {
    return invalid("sources[%u].prbs.amplitude = %g, expected a finite number", i, prbs.amplitude);
  }
  if (prbs.hold_samples == 0) {
    return invalid("sources[%u].prbs.hold_samples = 0, expected ≥ 1", i);
  }
  const std::uint32_t period = mseq_period(prbs.register_length);
  if (prbs.shift >= period) {
    return invalid("sources[%u].prbs.shift = %u, expected < 2^%u − 1 = %u bits", i, prbs.shift,
                   unsigned{prbs.register_length}, period);
  }
  return {};
}

Status check_multisine(std::uint32_t i, const MultisineSource& ms, const Recipe& recipe) {
  if (ms.period < 2 || ms.period > recipe.samples) {
    return invalid("sources[%u].multisine.period = %u, expected 2…samples = %u", i, ms.period,
                   recipe.samples);
  }
  const U64 end = U64{ms.first_line} + ms.line_count;
  if (end > recipe.line_count) {
    return invalid(
        "sources[%u].multisine.first_line + line_count = %u + %u = %llu, expected ≤ line_count "
        "= %u",
        i, ms.first_line, ms.line_count, end, recipe.line_count);
  }
  for (std::uint32_t l = ms.first_line; l < end; ++l) {
    const std::uint32_t index = recipe.lines[l].index;
    if (U64{index} * 2U >= ms.period) {
      return invalid(
          "lines[%u].index = %u, expected < period/2 = %g (Nyquist) of sources[%u].multisine", l,
          index, ms.period / 2.0, i);
    }
  }
  return {};
}

Status check_source(std::uint32_t i, const Source& source, const Recipe& recipe) {
  const U64 end = U64{source.start} + source.length;
  switch (source.kind) {
    case SourceKind::steps:
    case SourceKind::prbs:
    case SourceKind::multisine:
      break;
    default:
      return invalid("sources[%u].kind = %u, expected 1 (steps), 2 (prbs) or 3 (multisine)", i,
                     static_cast<unsigned>(source.kind));
  }
  if (end > recipe.samples) {
    return invalid("sources[%u].start + length = %u + %u = %llu, expected ≤ samples = %u", i,
                   source.start, source.length, end, recipe.samples);
  }
  switch (source.kind) {
    case SourceKind::steps:
      return check_steps(i, source.steps);
    case SourceKind::prbs:
      return check_prbs(i, source.prbs);
    default:
      return check_multisine(i, source.multisine, recipe);
  }
}

}  // namespace

Status validate(const Recipe& recipe, std::size_t table_capacity) {
  if (recipe.channels == 0 || recipe.channels > kMaxChannels) {
    return invalid("channels = %u, expected 1…%u", recipe.channels, kMaxChannels);
  }
  if (recipe.samples == 0) return invalid("samples = 0, expected ≥ 1");
  const U64 values = U64{recipe.channels} * recipe.samples;
  if (values > table_capacity) {
    return Status::error(StatusCode::capacity_exceeded,
                         "table of channels × samples = %u × %u = %llu values, expected ≤ "
                         "capacity %llu",
                         recipe.channels, recipe.samples, values, U64{table_capacity});
  }
  if (recipe.source_count > kMaxSources) {
    return Status::error(StatusCode::capacity_exceeded, "source_count = %u, expected ≤ %u",
                         recipe.source_count, kMaxSources);
  }
  if (recipe.line_count > kMaxLines) {
    return Status::error(StatusCode::capacity_exceeded, "line_count = %u, expected ≤ %u",
                         recipe.line_count, kMaxLines);
  }
  for (std::uint32_t i = 0; i < recipe.source_count; ++i) {
    if (Status s = check_source(i, recipe.sources[i], recipe); !s) return s;
  }
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    for (std::uint32_t i = 0; i < recipe.source_count; ++i) {
      if (!std::isfinite(recipe.mix[c][i])) {
        return invalid("mix[%u][%u] = %g, expected a finite number", c, i, recipe.mix[c][i]);
      }
    }
  }
  for (std::uint32_t l = 0; l < recipe.line_count; ++l) {
    const Line& line = recipe.lines[l];
    if (!std::isfinite(line.amplitude)) {
      return invalid("lines[%u].amplitude = %g, expected a finite number", l, line.amplitude);
    }
    if (!(std::fabs(line.phase) <= kMaxTrigArgument)) {
      return invalid("lines[%u].phase = %g rad, expected finite with |phase| ≤ %g", l, line.phase,
                     kMaxTrigArgument);
    }
  }
  return {};
}

}  // namespace excite::signal
