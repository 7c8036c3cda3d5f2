// SPDX-License-Identifier: MIT
#include "firmware/engine/engine.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/engine/table_checks.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine {

Status Engine::configure(const EngineConfig& config, signal::ConstTableView table) {
  if (Status s = validate(config); !s) return s;
  if (Status s = check_table_shape(table, config.inputs, "table"); !s) return s;
  *this = Engine{};
  config_ = config;
  table_ = table;
  configured_ = true;
  out_.inputs = config.inputs;
  return {};
}

Status Engine::arm(std::span<const double> live_values) {
  if (!configured_ || state_ != State::configured) {
    return Status::error(StatusCode::invalid_field, "engine state = %s, expected configured",
                         to_string(state_));
  }
  if (live_values.size() != config_.values) {
    return Status::error(StatusCode::invalid_field, "live values = %zu, expected %u",
                         live_values.size(), config_.values);
  }
  for (std::uint32_t j = 0; j < config_.values; ++j) {
    if (!std::isfinite(live_values[j])) {
      return Status::error(StatusCode::invalid_field, "value[%u] at arm = %g, expected finite", j,
                           live_values[j]);
    }
  }
  std::array<double, kMaxInputs> base{};
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    const InputLimits& in = config_.input[c];
    base[c] = live_values[static_cast<std::uint32_t>(in.readback)];
    if (base[c] < in.min || base[c] > in.max) {
      return Status::error(StatusCode::limit_violated,
                           "input[%u] baseline = %g (read back from value[%d]), expected within "
                           "[%g, %g]",
                           c, base[c], in.readback, in.min, in.max);
    }
  }
  if (Status s = check_table_range(config_, base, table_, "table"); !s) return s;
  base_u_ = base;
  for (std::uint32_t j = 0; j < config_.values; ++j) {
    base_y_[j] = live_values[j];
    last_y_[j] = live_values[j];
  }
  if (config_.command_value != kNone) {
    last_command_code_ = live_values[static_cast<std::uint32_t>(config_.command_value)];
    have_command_code_ = true;
    // A code left from before this run is not acted on; acknowledged, it is cleared.
    command_clear_due_ = config_.acknowledge_command && last_command_code_ != 0.0;
  }
  out_.setpoint = base_u_;
  out_.heartbeat = 0;
  excitation_.fill(0.0);
  written_.fill(base_u_);
  ramp_ = 0.0;
  armed_ = true;
  state_ = State::armed;
  return {};
}

Status Engine::check_quiet(std::span<const double> first, std::span<const double> second) {
  if (first.size() != config_.values || second.size() != config_.values) {
    return Status::error(StatusCode::invalid_field,
                         "values read before arm = %zu and %zu, expected %u", first.size(),
                         second.size(), config_.values);
  }
  // Not finite: arm() refuses it by name.
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    const auto j = static_cast<std::uint32_t>(config_.input[c].readback);
    if (!std::isfinite(first[j]) || !std::isfinite(second[j])) continue;
    if (readback_agrees(c, first[j], second[j])) continue;
    foreign_ = {true, true, false, c, config_.input[c].readback, first[j], second[j], 0};
    return Status::error(StatusCode::limit_violated,
                         "value[%d] (the readback of input[%u]) = %.9g then %.9g in two reads "
                         "before arm, expected unchanged (nothing was written)",
                         config_.input[c].readback, c, first[j], second[j]);
  }
  if (config_.heartbeat_echo != kNone) {
    const auto j = static_cast<std::uint32_t>(config_.heartbeat_echo);
    if (std::isfinite(first[j]) && std::isfinite(second[j]) && first[j] != second[j]) {
      foreign_ = {true, true, true, 0, config_.heartbeat_echo, first[j], second[j], 0};
      return Status::error(StatusCode::limit_violated,
                           "value[%d] (the heartbeat echo) = %.9g then %.9g in two reads before "
                           "arm, expected unchanged (nothing was written)",
                           config_.heartbeat_echo, first[j], second[j]);
    }
  }
  return {};
}

void Engine::foreign_seen(const ForeignWrite& what) noexcept {
  if (!foreign_.valid) foreign_ = what;
  foreign_now_ = true;
}

// Whether `limit_ns` has passed on the real clock since `since_ns` (started now when -1).
// Never without the real time (set_real_time) or without a limit.
bool Engine::real_time_passed(std::int64_t& since_ns, std::int64_t limit_ns) noexcept {
  if (!real_clock_ || limit_ns <= 0) return false;
  if (since_ns < 0) since_ns = now_ns_;
  return now_ns_ - since_ns >= limit_ns;
}

bool Engine::readback_agrees(std::uint32_t c, double written, double read) const noexcept {
  const InputLimits& in = config_.input[c];
  return std::abs(read - written) <= in.readback_abs_tol + in.readback_rel_tol * std::abs(written);
}

Status Engine::verify_arm(std::span<const double> values) {
  if (!armed_ || state_ != State::armed) {
    return Status::error(StatusCode::invalid_field, "engine state = %s, expected armed",
                         to_string(state_));
  }
  if (!config_.verify_readbacks) return {};
  if (values.size() != config_.values) {
    return Status::error(StatusCode::invalid_field, "values after the baseline = %zu, expected %u",
                         values.size(), config_.values);
  }
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    const auto j = static_cast<std::uint32_t>(config_.input[c].readback);
    if (readback_agrees(c, base_u_[c], values[j])) continue;
    fault_ = {true, true, c, config_.input[c].readback, base_u_[c], values[j], 0};
    armed_ = false;
    state_ = State::configured;
    return Status::error(StatusCode::limit_violated,
                         "input[%u]: wrote the baseline %.9g, read back %.9g from value[%d], "
                         "expected within %g",
                         c, base_u_[c], values[j], config_.input[c].readback,
                         config_.input[c].readback_abs_tol +
                             config_.input[c].readback_rel_tol * std::abs(base_u_[c]));
  }
  return {};
}

void Engine::apply_command() noexcept {
  const Command c = pending_;
  pending_ = Command::none;
  switch (c) {
    case Command::none:
      break;
    case Command::start:
      if (state_ == State::armed) state_ = State::running;
      break;
    case Command::suspend:
      if (state_ == State::running || state_ == State::suspended) reasons_ |= kReasonOperator;
      break;
    case Command::resume:
      reasons_ &= static_cast<std::uint8_t>(~kReasonOperator);
      break;
    case Command::approve:
      if (staged_.data != nullptr) staged_approved_ = true;
      break;
    case Command::abort:
      if (state_ == State::configured) {
        state_ = State::safe;
        outcome_ = Outcome::aborted_by_operator;
      } else if (state_ == State::armed || state_ == State::running || state_ == State::suspended) {
        state_ = State::aborted;
        outcome_ = Outcome::aborted_by_operator;
      }
      break;
  }
}

Status Engine::stage(signal::ConstTableView next, bool approved) noexcept {
  if (staged_.data != nullptr) {
    return Status::error(StatusCode::invalid_field,
                         "staged segment = already one (segment %u), expected none waiting",
                         segment_ + 1);
  }
  if (!(state_ == State::armed || state_ == State::running || state_ == State::suspended)) {
    return Status::error(StatusCode::invalid_field,
                         "engine state = %s, expected armed, running or suspended",
                         to_string(state_));
  }
  if (Status s = check_table_shape(next, config_.inputs, "segment table"); !s) return s;
  staged_ = next;
  staged_approved_ = approved;
  return {};
}

// The row about to be written (row_, already advanced) starts a period of the running table,
// or lies past its end.
bool Engine::at_segment_boundary() const noexcept {
  if (row_ >= table_.samples) return true;
  return config_.segment_period_rows != 0 && row_ % config_.segment_period_rows == 0;
}

bool Engine::awaiting_segment() const noexcept {
  if (config_.segment_await_ticks == 0 || await_over_) return false;
  if (state_ != State::running || reasons_ != 0) return false;
  if (pending_ == Command::abort || pending_ == Command::suspend) return false;
  if (!row_started_ || row_ + 1 < table_.samples) return false;
  const bool staged = staged_.data != nullptr;
  return !(staged && (staged_approved_ || pending_ == Command::approve));
}

// At the running table's end with no approved segment: hold (true) while the wait lasts,
// counted on the clock; false when it is off or over (the run completes).
bool Engine::hold_for_segment() noexcept {
  if (config_.segment_await_ticks == 0 || await_over_) return false;
  if (!awaiting_) {
    awaiting_ = true;
    awaited_ = 0;
  }
  awaited_ += elapsed_;
  if (awaited_ > config_.segment_await_ticks) {
    await_over_ = true;
    return false;
  }
  return true;
}

void Engine::fault(Outcome why) noexcept {
  if (state_ == State::armed || state_ == State::running || state_ == State::suspended) {
    state_ = State::aborted;
    outcome_ = why;
  }
}

void Engine::enter_suspended() noexcept {
  state_ = State::suspended;
  suspended_ticks_ = 0;
  suspended_since_ns_ = -1;
  ++suspensions_;
}

void Engine::enter_returning() noexcept {
  state_ = State::returning;
  returning_ticks_ = 0;
  confirm_ticks_ = 0;
  confirm_elapsed_ = 0;
  confirming_since_ns_ = -1;
  confirmed_once_ = false;
  stale_episode_ = false;
}

// Safe = the baseline read back on two exchanges at least confirm_hold_ticks apart, no
// failed exchange between them, within confirm_timeout_ticks of the output reaching it.
void Engine::confirm(bool out_at_baseline) noexcept {
  if (!out_at_baseline) return;  // still ramping out: the confirmation time starts at the baseline
  confirm_elapsed_ += elapsed_;  // on the clock: skipped ticks count
  // Lock-step: the confirmation time on the real clock too, whichever ends first.
  const bool real_over = real_time_passed(confirming_since_ns_, config_.confirm_timeout_ns);
  if (!exchange_ok_ || stale_) {
    confirmed_once_ = false;  // a failure means a reconnect: confirm afresh after it
  } else if (baseline_read_back_ && !controller_in_mode_) {
    confirmed_once_ = false;  // offsets at zero, but the controller is not in its mode
  } else if (baseline_read_back_) {
    stale_episode_ = false;
    if (!confirmed_once_) {
      confirmed_once_ = true;
      first_confirm_tick_ = ticks_;
    } else if (ticks_ - first_confirm_tick_ >= config_.confirm_hold_ticks) {
      state_ = State::safe;
      return;
    }
  } else if (mismatch_now_) {
    // The device holds another value than the baseline written: a write applied late. The
    // baseline goes out again every tick; counted once per episode.
    if (!stale_episode_) ++stale_undone_;
    stale_episode_ = true;
    confirmed_once_ = false;
  }
  if (confirm_elapsed_ >= config_.confirm_timeout_ticks || real_over) {
    state_ = State::safe_unconfirmed;
  }
}

// Running: the next row of the table; at a boundary the approved segment's row 0; at the
// table's end the wait for a segment (holding the operating point) or completion.
void Engine::advance_row() noexcept {
  if (row_started_) ++row_;
  row_started_ = true;
  if (row_ != 0 && staged_approved_ && at_segment_boundary()) switch_segment();
  if (row_ >= table_.samples) {  // the last row was written last tick
    row_ = table_.samples - 1;
    if (hold_for_segment()) {  // the operating point, until a segment or the wait's end
      for (std::uint32_t c = 0; c < config_.inputs; ++c) excitation_[c] = 0.0;
      flags_ |= runlog::kSuspended;
      ++awaited_total_;
    } else {
      state_ = State::completed;
      outcome_ = Outcome::completed;
    }
  } else {
    for (std::uint32_t c = 0; c < config_.inputs; ++c) excitation_[c] = table_.at(row_, c);
  }
}

// The approved segment replaces the running table; this tick writes its row 0.
void Engine::switch_segment() noexcept {
  table_ = staged_;
  staged_ = {};
  staged_approved_ = false;
  row_ = 0;
  ++segment_;
  awaiting_ = false;
  await_over_ = false;  // the new table's end has a wait of its own
}

// The excitation's scale moves towards its goal by 1/ramp_ticks per tick: ramp-in when
// running, ramp-out otherwise; held while suspended on comm loss with action hold.
void Engine::move_ramp() noexcept {
  double goal = state_ == State::running ? 1.0 : 0.0;
  if (state_ == State::suspended && (reasons_ & kReasonComm) != 0 &&
      config_.comm_loss == CommLossAction::hold) {
    goal = ramp_;
  }
  const double step = config_.ramp_ticks == 0 ? 1.0 : 1.0 / config_.ramp_ticks;
  ramp_ = goal > ramp_ ? std::min(goal, ramp_ + step) : std::max(goal, ramp_ - step);
  if (state_ == State::suspended) flags_ |= runlog::kSuspended;
}

// Baseline + ramp · excitation, clamped to each input's limits, then rate-limited by
// max_move against the setpoint written last; the row's flags say which acted.
void Engine::limit_setpoints() noexcept {
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    const InputLimits& in = config_.input[c];
    double target = base_u_[c] + ramp_ * excitation_[c];
    if (ramp_ == 0.0) target = base_u_[c];
    if (target < in.min || target > in.max) {
      target = std::clamp(target, in.min, in.max);
      flags_ |= runlog::kClamped;
    }
    const double previous = out_.setpoint[c];
    if (target - previous > in.max_move) {
      target = previous + in.max_move;
      flags_ |= runlog::kRateLimited;
    } else if (previous - target > in.max_move) {
      target = previous - in.max_move;
      flags_ |= runlog::kRateLimited;
    }
    out_.setpoint[c] = target;
  }
}

const TickOutput& Engine::compute(std::uint64_t skipped_ticks) noexcept {
  flags_ = 0;
  elapsed_ = 1;
  if (state_ == State::completed || state_ == State::aborted) enter_returning();
  apply_command();
  if (state_ == State::running && reasons_ != 0) enter_suspended();
  if (state_ == State::suspended && reasons_ == 0) state_ = State::running;
  if (state_ == State::configured || !armed_) {
    out_.write = false;
    return out_;
  }
  out_.write = true;
  out_.heartbeat = static_cast<std::uint16_t>(out_.heartbeat + 1U);
  if (skipped_ticks != 0 && ticks_ != 0) {  // before the first tick there is nothing to skip
    ticks_ += skipped_ticks;
    skipped_total_ += skipped_ticks;
    elapsed_ += skipped_ticks;
    flags_ |= runlog::kSkipped;
  }
  ++ticks_;
  ++writes_;

  if (state_ == State::running) advance_row();
  move_ramp();
  limit_setpoints();
  written_[writes_ % kMaxReadbackLag] = out_.setpoint;
  return out_;
}

void Engine::check_comm(bool exchange_ok, std::span<const double> values) noexcept {
  if (!exchange_ok) {
    ++fail_streak_;
    ++failed_total_;
  } else {
    fail_streak_ = 0;
  }
  stale_ = false;
  if (exchange_ok && config_.heartbeat_echo != kNone && writes_ > config_.heartbeat_max_lag) {
    const double echo = values[static_cast<std::uint32_t>(config_.heartbeat_echo)];
    if (!(echo >= 0.0 && echo <= 65535.0)) {
      stale_ = true;
    } else {
      const auto seen = static_cast<std::uint16_t>(std::lround(echo));
      const auto lag = static_cast<std::uint16_t>(out_.heartbeat - seen);
      stale_ = lag > config_.heartbeat_max_lag;
      // One owner: on a link without a failure since the last echo, the echo moves forward
      // by at most the heartbeats sent since (a slow peer lags, it never goes back or ahead);
      // otherwise another master wrote the heartbeat register. (After a failure the peer
      // may have restarted: check_peer_continuity's discontinuity. While returning a write
      // in flight when the peer froze may land late: confirm() undoes it.)
      const auto moved = static_cast<std::uint16_t>(seen - last_echo_);
      const auto sent = static_cast<std::uint16_t>(out_.heartbeat - last_echo_);
      if (have_echo_ && previous_ok_ && state_ != State::returning && moved > sent) {
        foreign_seen({true, false, true, 0, config_.heartbeat_echo,
                      static_cast<double>(out_.heartbeat), echo, ticks_ == 0 ? 0 : ticks_ - 1});
      }
      last_echo_ = seen;
      have_echo_ = true;
    }
  }
  if (fail_streak_ >= config_.comm_fail_limit || stale_) {
    if ((reasons_ & kReasonComm) == 0) ++comm_losses_;
    reasons_ |= kReasonComm;
    comm_ok_streak_ = 0;
  } else if ((reasons_ & kReasonComm) != 0 && exchange_ok) {
    if (++comm_ok_streak_ >= config_.resume_dwell_ticks) {
      reasons_ &= static_cast<std::uint8_t>(~kReasonComm);
      comm_ok_streak_ = 0;
    }
  }
}

void Engine::check_peer_continuity(std::span<const double> values) noexcept {
  if (!armed_ || !have_echo_ || config_.heartbeat_echo == kNone || values.size() < config_.values) {
    return;
  }
  const double echo = values[static_cast<std::uint32_t>(config_.heartbeat_echo)];
  bool continuous = false;
  if (echo >= 0.0 && echo <= 65535.0) {
    const auto seen = static_cast<std::uint16_t>(std::lround(echo));
    // Forward distance from the last echo seen, against the heartbeats sent since (this
    // tick's included: computed, not yet written). Modulo 2^16, as the counter wraps.
    const auto moved = static_cast<std::uint16_t>(seen - last_echo_);
    const auto sent = static_cast<std::uint16_t>(out_.heartbeat - last_echo_);
    continuous = moved <= sent;
  }
  if (!continuous) {
    flags_ |= runlog::kDiscontinuity;
    ++discontinuities_;
  }
}

void Engine::check_before_write(std::span<const double> values) noexcept {
  if (!armed_ || !previous_ok_ || state_ == State::returning || values.size() < config_.values) {
    return;
  }
  const std::uint64_t tick = ticks_ == 0 ? 0 : ticks_ - 1;
  if (config_.heartbeat_echo != kNone && have_echo_) {
    const double echo = values[static_cast<std::uint32_t>(config_.heartbeat_echo)];
    if (echo >= 0.0 && echo <= 65535.0) {
      const auto seen = static_cast<std::uint16_t>(std::lround(echo));
      // The heartbeats sent before this tick's (computed, not yet written).
      const auto last_sent = static_cast<std::uint16_t>(out_.heartbeat - 1U);
      const auto moved = static_cast<std::uint16_t>(seen - last_echo_);
      const auto sent = static_cast<std::uint16_t>(last_sent - last_echo_);
      if (moved > sent) {
        foreign_seen({true, false, true, 0, config_.heartbeat_echo, static_cast<double>(last_sent),
                      echo, tick});
        return;
      }
    }
  }
  if (!config_.verify_readbacks) return;
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    if (!last_agreed_[c]) continue;
    const double read = values[static_cast<std::uint32_t>(config_.input[c].readback)];
    if (!wrote_lately(c, read)) {
      foreign_seen(
          {true, false, false, c, config_.input[c].readback, last_compared_[c], read, tick});
      return;
    }
  }
}

bool Engine::wrote_lately(std::uint32_t c, double read) const noexcept {
  for (const auto& w : written_) {
    if (readback_agrees(c, w[c], read)) return true;
  }
  return false;
}

void Engine::check_controller(bool exchange_ok, std::span<const double> values) noexcept {
  const ControllerWatch& w = config_.controller;
  if (w.mode == kNone || !exchange_ok) return;  // silence is the comm guard's
  const double mode = values[static_cast<std::uint32_t>(w.mode)];
  bool in_mode = mode == 1.0 || mode == 2.0;  // control or test
  bool limited = false;
  for (std::uint32_t i = 0; i < w.mvs; ++i) {
    const double s = values[static_cast<std::uint32_t>(w.status[i])];
    if (s == 1.0 || s == 2.0 || s == 3.0) limited = true;  // clamped low/high, windup
    if (s == 4.0) in_mode = false;                         // manual
  }
  if (!in_mode && controller_in_mode_) ++mode_losses_;
  if (limited && !mv_limited_now_) ++mv_limited_;
  controller_in_mode_ = in_mode;
  mv_limited_now_ = limited;
  if (!in_mode || limited) {
    reasons_ |= kReasonController;
    controller_ok_streak_ = 0;
  } else if ((reasons_ & kReasonController) != 0 &&
             ++controller_ok_streak_ >= config_.resume_dwell_ticks) {
    reasons_ &= static_cast<std::uint8_t>(~kReasonController);
    controller_ok_streak_ = 0;
  }
}

void Engine::check_limits(bool exchange_ok, std::span<const double> values) noexcept {
  if (!exchange_ok) return;  // nothing new to judge; the comm guard handles silence
  bool outside = false;
  bool inside_band = true;
  for (std::uint32_t j = 0; j < config_.values; ++j) {
    const TestLimit& t = config_.test[j];
    if (!t.enabled) continue;
    const double v = values[j];
    if (!(v >= t.low && v <= t.high)) outside = true;  // NaN counts as outside
    if (!(v >= t.low + t.hysteresis && v <= t.high - t.hysteresis)) inside_band = false;
  }
  if (outside) {
    reasons_ |= kReasonLimit;
    inside_streak_ = 0;
  } else if ((reasons_ & kReasonLimit) != 0) {
    if (!inside_band) {
      inside_streak_ = 0;
    } else if (++inside_streak_ >= config_.resume_dwell_ticks) {
      reasons_ &= static_cast<std::uint8_t>(~kReasonLimit);
      inside_streak_ = 0;
    }
  }
}

void Engine::read_command_register(bool exchange_ok, std::span<const double> values) noexcept {
  if (!exchange_ok || config_.command_value == kNone) return;
  const double code = values[static_cast<std::uint32_t>(config_.command_value)];
  if (!std::isfinite(code)) return;
  if (!have_command_code_ || code != last_command_code_) {
    last_command_code_ = code;
    have_command_code_ = true;
    const Command c = command_from_code(std::llround(code));
    if (c != Command::none) pending_ = c;
  }
  command_clear_due_ = config_.acknowledge_command && code != 0.0;
}

void Engine::command_cleared() noexcept {
  if (!command_clear_due_) return;
  command_clear_due_ = false;
  last_command_code_ = 0.0;  // what the register holds now: the next code is an edge
  ++acknowledged_;
}

// Verified writes: the reading of tick t reflects the write of tick t − (lag − 1); before
// tick 1 the baseline was written (arm). More than readback_mismatch_limit consecutive
// mismatches on one setpoint is a fault: excitation stops (aborted → returning).
void Engine::check_readbacks(std::span<const double> values) noexcept {
  baseline_read_back_ = false;
  mismatch_now_ = false;
  if (!exchange_ok_) return;  // previous_ok_ is false on the next tick
  if (!config_.verify_readbacks) {
    baseline_read_back_ = true;
    return;
  }
  const std::uint64_t lag = config_.readback_lag_ticks;
  const bool after_arm = writes_ + 1 > lag;
  // A ring index below kMaxReadbackLag: fits std::size_t on 32-bit targets too.
  const auto slot = static_cast<std::size_t>(after_arm ? (writes_ + 1 - lag) % kMaxReadbackLag : 0);
  bool all_at_baseline = true;
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    const double written = after_arm ? written_[slot][c] : base_u_[c];
    const auto j = static_cast<std::uint32_t>(config_.input[c].readback);
    const double read = values[j];
    const bool agrees = readback_agrees(c, written, read);
    // One owner: the same value written on this tick and the last, read back last tick, now
    // reads a value this gateway never wrote lately, on a link without a failure — another
    // master wrote it. (A peer faster than readback_lag_ticks — CAN frames sent on the
    // peer's own cycle — shows a newer write of ours: not foreign.) Not while returning: a
    // write applied late by a peer that froze is undone there (confirm()).
    if (previous_ok_ && state_ != State::returning && last_agreed_[c] &&
        last_compared_[c] == written && !agrees && !wrote_lately(c, read)) {
      foreign_seen({true, false, false, c, config_.input[c].readback, written, read,
                    ticks_ == 0 ? 0 : ticks_ - 1});
    }
    last_compared_[c] = written;
    last_agreed_[c] = agrees;
    if (agrees) {
      mismatch_streak_[c] = 0;
      if (written != base_u_[c]) all_at_baseline = false;
      continue;
    }
    all_at_baseline = false;
    mismatch_now_ = true;
    ++mismatches_total_;
    // With confirmation on, a mismatch while returning is a stale write being undone
    // (confirm()), not a fault.
    const bool undoing = config_.confirm_timeout_ticks != 0 && state_ == State::returning;
    if (++mismatch_streak_[c] > config_.readback_mismatch_limit && !fault_.valid && !undoing) {
      fault_ = {true, false, c, config_.input[c].readback, written, read, ticks_};
      outcome_ = Outcome::readback_fault;
      if (state_ == State::armed || state_ == State::running || state_ == State::suspended) {
        state_ = State::aborted;
      }
    }
  }
  baseline_read_back_ = all_at_baseline;
}

void Engine::count_flags() noexcept {
  for (std::size_t b = 0; b < flag_rows_.size(); ++b) {
    if ((flags_ & (1U << b)) != 0U) ++flag_rows_[b];
  }
}

std::uint64_t Engine::rows_flagged(std::uint32_t flag) const noexcept {
  for (std::size_t b = 0; b < flag_rows_.size(); ++b) {
    if (flag == (1U << b)) return flag_rows_[b];
  }
  return 0;
}

bool Engine::at_baseline() const noexcept {
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    if (out_.setpoint[c] != base_u_[c]) return false;
  }
  return true;
}

// Suspended: a limit or comm suspension aborts after suspend_timeout (ticks on the plan's
// clock, or the real time in lock-step); a controller suspension after its own timeout.
void Engine::judge_suspension() noexcept {
  if ((reasons_ & (kReasonLimit | kReasonComm)) != 0) {
    suspended_ticks_ += elapsed_;  // on the clock: skipped ticks count
    const bool real_over = real_time_passed(suspended_since_ns_, config_.suspend_timeout_ns);
    if ((config_.suspend_timeout_ticks != 0 && suspended_ticks_ >= config_.suspend_timeout_ticks) ||
        real_over) {
      state_ = State::aborted;
      outcome_ = Outcome::aborted_on_timeout;
    }
  }
  if ((reasons_ & kReasonController) == 0) {
    controller_ticks_ = 0;
    controller_since_ns_ = -1;
  } else if (state_ == State::suspended) {
    controller_ticks_ += elapsed_;
    const bool real_over = real_time_passed(controller_since_ns_, config_.controller.timeout_ns);
    if ((config_.controller.timeout_ticks != 0 &&
         controller_ticks_ >= config_.controller.timeout_ticks) ||
        real_over) {
      state_ = State::aborted;
      outcome_ = Outcome::aborted_on_controller;
    }
  }
}

// Returning: safe once the baseline is out and read back (confirm() with a confirmation
// timeout), else safe_unconfirmed after the window.
void Engine::judge_return() noexcept {
  returning_ticks_ += elapsed_;  // on the clock: skipped ticks count
  const bool out_at_baseline = ramp_ == 0.0 && at_baseline();
  if (config_.confirm_timeout_ticks != 0) {
    confirm(out_at_baseline);
    return;
  }
  if (out_at_baseline) ++confirm_ticks_;
  // Safe = the baseline was written and read back; otherwise, after the confirmation
  // window, safe_unconfirmed (the link stays down, or the readbacks disagree).
  const std::uint64_t window = std::max<std::uint64_t>(
      config_.suspend_timeout_ticks,
      std::uint64_t{config_.readback_lag_ticks} + config_.readback_mismatch_limit + 1);
  if (out_at_baseline && exchange_ok_ && !stale_ && baseline_read_back_ && controller_in_mode_) {
    state_ = State::safe;
  } else if ((reasons_ & kReasonComm) != 0) {
    if (config_.suspend_timeout_ticks != 0 &&
        returning_ticks_ >= std::uint64_t{config_.ramp_ticks} + config_.suspend_timeout_ticks) {
      state_ = State::safe_unconfirmed;
    }
  } else if (confirm_ticks_ > window) {
    state_ = State::safe_unconfirmed;
  }
}

void Engine::observe(bool exchange_ok, std::span<const double> values, bool refused) noexcept {
  if (!armed_) return;  // nothing was written, nothing to judge
  exchange_ok_ = exchange_ok && values.size() >= config_.values;
  refused = refused && !exchange_ok_;
  // With the real time (lock-step), a failed exchange took none of the peer's time: the
  // timeouts count it on the real clock only.
  if (real_clock_ && !exchange_ok_) elapsed_ = 0;
  if (refused) {  // the device's answer, not a lost link: not the comm guard's
    ++failed_total_;
    stale_ = false;
  } else {
    check_comm(exchange_ok_, values);
  }
  if (exchange_ok_) {
    for (std::uint32_t j = 0; j < config_.values; ++j) last_y_[j] = values[j];
  }
  check_limits(exchange_ok_, values);
  check_controller(exchange_ok_, values);
  read_command_register(exchange_ok_, values);
  check_readbacks(values);
  if ((!exchange_ok_ && !refused) || (reasons_ & kReasonComm) != 0) flags_ |= runlog::kCommLost;
  if (stale_) flags_ |= runlog::kStale;
  count_flags();

  switch (state_) {
    case State::running:
      if (reasons_ != 0) enter_suspended();
      break;
    case State::suspended:
      judge_suspension();
      break;
    case State::returning:
      judge_return();
      break;
    default:
      break;
  }
  // Another master's write stops the excitation like any fault; a run already returning
  // keeps returning, and its outcome says what was seen.
  if (foreign_now_) {
    foreign_now_ = false;
    if (state_ == State::armed || state_ == State::running || state_ == State::suspended) {
      state_ = State::aborted;
    }
    outcome_ = Outcome::foreign_writer;
  }
  previous_ok_ = exchange_ok_;
}

TickRecord Engine::record(std::int64_t time_ns) const noexcept {
  TickRecord r;
  r.time_ns = time_ns;
  r.tick = ticks_ == 0 ? 0 : ticks_ - 1;
  r.row = row_;
  r.segment = segment_;
  r.state = state_;
  r.flags = flags_;
  for (std::uint32_t c = 0; c < config_.inputs; ++c) {
    r.u[c] = out_.setpoint[c];
    r.du[c] = out_.setpoint[c] - base_u_[c];
  }
  for (std::uint32_t j = 0; j < config_.values; ++j) r.dy[j] = last_y_[j] - base_y_[j];
  const ControllerWatch& w = config_.controller;
  if (w.mode == kNone) return r;
  r.closed_loop = true;
  r.mvs = w.mvs;
  r.cvs = w.cvs;
  const auto read = [this](std::int32_t index) {
    return index == kNone ? 0.0 : last_y_[static_cast<std::uint32_t>(index)];
  };
  for (std::uint32_t c = 0; c < config_.inputs; ++c) r.r[c] = r.du[c];
  for (std::uint32_t i = 0; i < w.mvs; ++i) {
    r.uc[i] = read(w.move[i]);
    r.du_applied[i] = read(w.applied[i]);
    const double s = read(w.status[i]);
    r.st[i] = s >= 0.0 && s <= 255.0 ? static_cast<std::uint8_t>(s) : 255;
  }
  for (std::uint32_t j = 0; j < w.cvs; ++j) r.ysp[j] = read(w.setpoint[j]);
  const double mode = read(w.mode);
  r.mode = mode >= 0.0 && mode <= 255.0 ? static_cast<std::uint8_t>(mode) : 255;
  return r;
}

}  // namespace excite::engine
