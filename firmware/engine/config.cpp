// SPDX-License-Identifier: MIT
#include "firmware/engine/config.hpp"

#include <cmath>
#include <initializer_list>

namespace excite::engine {

namespace {

bool valid_index(std::int32_t index, std::uint32_t count) {
  return index == kNone || (index >= 0 && static_cast<std::uint32_t>(index) < count);
}

// Each input's limits, move and readback; the readback lag.
Status validate_inputs(const EngineConfig& config) {
  for (std::uint32_t c = 0; c < config.inputs; ++c) {
    const InputLimits& in = config.input[c];
    if (!std::isfinite(in.min) || !std::isfinite(in.max) || in.min > in.max) {
      return Status::error(StatusCode::invalid_field,
                           "input[%u].min, max = %g, %g, expected finite with min <= max", c,
                           in.min, in.max);
    }
    if (!std::isfinite(in.max_move) || in.max_move <= 0.0) {
      return Status::error(StatusCode::invalid_field, "input[%u].max_move = %g, expected > 0", c,
                           in.max_move);
    }
    if (in.readback == kNone || !valid_index(in.readback, config.values)) {
      return Status::error(StatusCode::invalid_field,
                           "input[%u].readback = %d, expected a value index 0…%u", c, in.readback,
                           config.values - 1);
    }
    if (!(in.readback_abs_tol >= 0.0) || !(in.readback_rel_tol >= 0.0)) {
      return Status::error(StatusCode::invalid_field,
                           "input[%u].readback_abs_tol, readback_rel_tol = %g, %g, expected >= 0",
                           c, in.readback_abs_tol, in.readback_rel_tol);
    }
  }
  if (config.readback_lag_ticks < 1 || config.readback_lag_ticks > kMaxReadbackLag) {
    return Status::error(StatusCode::invalid_field, "readback_lag_ticks = %u, expected 1…%u",
                         config.readback_lag_ticks, kMaxReadbackLag);
  }
  return {};
}

// The test limits of the values that have them.
Status validate_test_limits(const EngineConfig& config) {
  for (std::uint32_t j = 0; j < config.values; ++j) {
    const TestLimit& t = config.test[j];
    if (!t.enabled) continue;
    if (!std::isfinite(t.low) || !std::isfinite(t.high) || t.low >= t.high) {
      return Status::error(StatusCode::invalid_field,
                           "test[%u].low, high = %g, %g, expected finite with low < high", j, t.low,
                           t.high);
    }
    if (!std::isfinite(t.hysteresis) || t.hysteresis < 0.0 ||
        2.0 * t.hysteresis >= t.high - t.low) {
      return Status::error(StatusCode::invalid_field,
                           "test[%u].hysteresis = %g, expected 0 <= 2 * hysteresis < high - low "
                           "= %g",
                           j, t.hysteresis, t.high - t.low);
    }
  }
  return {};
}

// The durations, in ticks, each within kMaxDurationTicks.
Status validate_durations(const EngineConfig& config) {
  if (config.resume_dwell_ticks < 1 || config.resume_dwell_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field, "resume_dwell_ticks = %u, expected 1…%u",
                         config.resume_dwell_ticks, kMaxDurationTicks);
  }
  if (config.ramp_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field, "ramp_ticks = %u, expected 0…%u",
                         config.ramp_ticks, kMaxDurationTicks);
  }
  if (config.suspend_timeout_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field,
                         "suspend_timeout_ticks = %u, expected 0 (never) or 1…%u",
                         config.suspend_timeout_ticks, kMaxDurationTicks);
  }
  if (config.confirm_timeout_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field,
                         "confirm_timeout_ticks = %u, expected 0 (the older window) or 1…%u",
                         config.confirm_timeout_ticks, kMaxDurationTicks);
  }
  if (config.confirm_hold_ticks < 1 || config.confirm_hold_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field, "confirm_hold_ticks = %u, expected 1…%u",
                         config.confirm_hold_ticks, kMaxDurationTicks);
  }
  if (config.segment_await_ticks > kMaxDurationTicks) {
    return Status::error(StatusCode::invalid_field,
                         "segment_await_ticks = %u, expected 0 (complete at the table's end) "
                         "or 1…%u",
                         config.segment_await_ticks, kMaxDurationTicks);
  }
  return {};
}

// The comm guard, the heartbeat echo and the command register.
Status validate_value_roles(const EngineConfig& config) {
  if (config.comm_fail_limit < 1) {
    return Status::error(StatusCode::invalid_field, "comm_fail_limit = 0, expected >= 1");
  }
  if (!valid_index(config.heartbeat_echo, config.values)) {
    return Status::error(StatusCode::invalid_field,
                         "heartbeat_echo = %d, expected -1 (none) or a value index 0…%u",
                         config.heartbeat_echo, config.values - 1);
  }
  if (config.heartbeat_echo != kNone &&
      (config.heartbeat_max_lag < 1 || config.heartbeat_max_lag > kMaxHeartbeatLagTicks)) {
    return Status::error(StatusCode::invalid_field, "heartbeat_max_lag = %u, expected 1…%u",
                         config.heartbeat_max_lag, kMaxHeartbeatLagTicks);
  }
  if (!valid_index(config.command_value, config.values)) {
    return Status::error(StatusCode::invalid_field,
                         "command_value = %d, expected -1 (none) or a value index 0…%u",
                         config.command_value, config.values - 1);
  }
  return {};
}

// Closed loop: the controller's read-backs and timeout.
Status validate_controller(const EngineConfig& config) {
  const ControllerWatch& w = config.controller;
  if (!valid_index(w.mode, config.values)) {
    return Status::error(StatusCode::invalid_field,
                         "controller.mode = %d, expected -1 (open loop) or a value index 0…%u",
                         w.mode, config.values - 1);
  }
  if (w.mode != kNone) {
    if (w.mvs > kMaxInputs || w.cvs > kMaxInputs) {
      return Status::error(StatusCode::invalid_field,
                           "controller.mvs = %u, cvs = %u, expected at most %u each", w.mvs, w.cvs,
                           kMaxInputs);
    }
    for (std::uint32_t i = 0; i < w.mvs; ++i) {
      if (w.status[i] == kNone || !valid_index(w.status[i], config.values) ||
          !valid_index(w.move[i], config.values) || !valid_index(w.applied[i], config.values)) {
        return Status::error(StatusCode::invalid_field,
                             "controller.status[%u] = %d, expected a value index 0…%u (and "
                             "move, applied -1 or a value index)",
                             i, w.status[i], config.values - 1);
      }
    }
    for (std::uint32_t j = 0; j < w.cvs; ++j) {
      if (w.setpoint[j] == kNone || !valid_index(w.setpoint[j], config.values)) {
        return Status::error(StatusCode::invalid_field,
                             "controller.setpoint[%u] = %d, expected a value index 0…%u", j,
                             w.setpoint[j], config.values - 1);
      }
    }
    if (w.timeout_ticks > kMaxDurationTicks || w.timeout_ns < 0) {
      return Status::error(StatusCode::invalid_field,
                           "controller.timeout_ticks = %u, expected 0 (never) or 1…%u",
                           w.timeout_ticks, kMaxDurationTicks);
    }
  }
  return {};
}

}  // namespace

Status validate(const EngineConfig& config) {
  if (config.inputs < 1 || config.inputs > kMaxInputs) {
    return Status::error(StatusCode::invalid_field, "inputs = %u, expected 1…%u", config.inputs,
                         kMaxInputs);
  }
  if (config.values < 1 || config.values > kMaxValues) {
    return Status::error(StatusCode::invalid_field, "values = %u, expected 1…%u", config.values,
                         kMaxValues);
  }
  for (Status (*part)(const EngineConfig&) :
       {validate_inputs, validate_test_limits, validate_durations, validate_value_roles,
        validate_controller}) {
    if (Status s = part(config); !s) return s;
  }
  return {};
}

}  // namespace excite::engine
