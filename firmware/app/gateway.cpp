// SPDX-License-Identifier: MIT
#include "firmware/app/gateway.hpp"

#include <cmath>
#include <cstdio>

#include "base/config/document.hpp"
#include "firmware/engine/load_plan.hpp"

namespace excite::app {

Gateway::Gateway(GatewayConfig config) : config_(std::move(config)) {}

Gateway::~Gateway() = default;  // LogDrain's destructor stops the log thread if still running

StageResult Gateway::load_plan(std::span<const std::uint8_t> plan_file, std::string plan_name) {
  plan_name_ = std::move(plan_name);
  plan_ = std::make_unique<plan::Plan>();
  if (auto s = engine::load_plan(plan_file, static_cast<std::uint32_t>(config_.setpoints.size()),
                                 signal::kTableCapacity, *plan_, streamed_excitation(config_));
      !s) {
    return StageError{ExitCode::bad_plan, plan_name_ + ": " + s.message()};
  }
  storage_.assign(signal::kTableCapacity, 0.0);
  {
    std::vector<double> scratch(signal::scratch_size(plan_->recipe));
    if (auto s = engine::make_table(*plan_, storage_, scratch, table_); !s) {
      return StageError{ExitCode::bad_plan, plan_name_ + ": " + s.message()};
    }
  }
  sample_time_ = Minutes(plan_->meta.sample_time_min);
  const std::chrono::duration<double> period =
      config_.period_s ? std::chrono::duration<double>(*config_.period_s)
                       : std::chrono::duration<double>(sample_time_);
  if (std::string e = check_timing(config_, period); !e.empty()) {
    return StageError{ExitCode::bad_config, e};
  }
  period_ = std::chrono::round<hal::Nanoseconds>(period);
  engine_config_ = to_engine_config(config_, period);
  engine_ = std::make_unique<engine::Engine>();
  if (auto s = engine_->configure(engine_config_, table_); !s) {
    return StageError{ExitCode::bad_config, config_.source + ": " + s.message()};
  }
  // Outputs and readbacks carried by a bounded register are watched for readings at its
  // end (a quarter of one raw count inside it, or beyond).
  const std::vector<hal::CarriedRange> ranges = carried_ranges(config_, hal::ChannelKind::value);
  range_what_.assign(config_.values.size(), std::string());
  for (std::size_t j = 0; j < ranges.size() && j < config_.values.size(); ++j) {
    const ValueRole role = config_.values[j].role;
    if (!ranges[j].bounded || (role != ValueRole::output && role != ValueRole::readback)) {
      continue;
    }
    range_ends_[j] = {true, ranges[j].low + 0.25 * ranges[j].count,
                      ranges[j].high - 0.25 * ranges[j].count};
    range_what_[j] = ranges[j].what;
  }
  return std::nullopt;
}

StageResult Gateway::arm(hal::FieldBus& bus, hal::Clock& clock) {
  ring_storage_.assign(config_.log_ring, engine::TickRecord{});  // sized once
  ring_ = std::make_unique<engine::SpanLogRing>(ring_storage_);
  runner_ = std::make_unique<Runner>(*engine_, bus, clock, *ring_, period_);
  runner_->watch_range_ends(
      std::span<const RangeEnd>(range_ends_.data(), config_.values.size()),
      std::span<std::uint64_t>(range_end_counts_.data(), config_.values.size()));
  runner_->set_verify_at_arm(verify_at_arm_);
  runner_->observe_quiet(quiet_clock_, quiet_interval_);
  if (auto s = runner_->arm(); !s) {
    if (engine_->foreign_write().valid) {
      return StageError{ExitCode::arm_refused, "refused to arm: " + foreign_write_report()};
    }
    if (engine_->readback_fault().valid) {
      return StageError{ExitCode::arm_refused,
                        "refused to arm: verified write failed: " + readback_fault_report()};
    }
    return StageError{ExitCode::arm_refused, "refused to arm: " + std::string(s.message())};
  }
  return std::nullopt;
}

StageResult Gateway::start_log(std::FILE* file, std::string producer) {
  producer_ = std::move(producer);
  inputs_.clear();
  outputs_.clear();
  LogLayout layout;
  layout.output_values = output_indices(config_);
  if (config_.closed_loop) {  // run-log v4: the MVs are the inputs, the offsets r
    layout.closed = closed_loop_log_layout(config_, layout.output_values.size(), inputs_);
    layout.header.closed_loop.closed = true;
    layout.header.closed_loop.excitation = layout.closed.excitation;
    layout.header.closed_loop.controller = config_.closed_loop->controller.empty()
                                               ? std::string_view("unknown (not configured)")
                                               : std::string_view(config_.closed_loop->controller);
  } else {
    for (const auto& s : config_.setpoints) inputs_.push_back({s.name, s.unit});
  }
  for (int j : layout.output_values) {
    const ValueSpec& v = config_.values[static_cast<std::size_t>(j)];
    outputs_.push_back({v.name, v.unit});
  }
  layout.header.producer = producer_;
  layout.header.plant = config_.plant;
  layout.header.plan = plan_name_;
  layout.header.sample_time_min = sample_time_.count();  // the plan's T, minutes
  layout.header.time_scales = {plan_->meta.tau_high_min, plan_->meta.beta,
                               plan_->meta.switch_time_min};  // the design's, for identify
  layout.header.inputs = inputs_;
  layout.header.outputs = outputs_;
  drain_ = std::make_unique<LogDrain>(*ring_, file, std::move(layout));
  drain_->set_event_stream(events_);
  drain_->set_row_delay(row_delay_);
  drain_->set_max_bytes(static_cast<std::uint64_t>(config_.log_max_mb * 1e6), config_.log_max_mb);
  if (!drain_->write_header()) {
    drain_->stop();  // done with the FILE: the caller closes it
    return StageError{ExitCode::log_error, drain_->failure()};
  }
  runner_->watch_log(&drain_->failed());
  drain_->start();
  return std::nullopt;
}

void Gateway::start_segments(std::string dir, bool allow_distortion, std::FILE* events,
                             std::string run_id) {
  spare_storage_.assign(signal::kTableCapacity, 0.0);  // sized once, before the run
  SegmentInboxSetup setup;
  setup.dir = std::move(dir);
  setup.config = &config_;
  setup.engine_config = engine_config_;
  setup.running = plan_.get();
  for (std::uint32_t c = 0; c < engine_config_.inputs; ++c)
    setup.baseline[c] = engine_->baseline(c);
  setup.buffers = {std::span<double>(storage_), std::span<double>(spare_storage_)};
  setup.allow_distortion = allow_distortion;
  setup.events = events;
  setup.run_id = std::move(run_id);
  inbox_ = std::make_unique<SegmentInbox>(std::move(setup));
  runner_->watch_segments(&inbox_->handoff());
  inbox_->start();
}

void Gateway::stop_segments() {
  if (inbox_) inbox_->stop();
}

RunStats Gateway::run(CommandMailbox& commands, const std::atomic<bool>* stop,
                      std::uint64_t max_ticks) noexcept {
  runner_->set_observer(observer_);
  runner_->pace_retries(pacing_clock_, retry_interval_);
  runner_->time_on_real_clock(real_time_);
  runner_->read_before_write(read_before_write_);
  if (await_clock_ != nullptr && config_.segment_await_s > 0.0) {
    runner_->await_segments_on(await_clock_,
                               std::chrono::round<hal::Nanoseconds>(
                                   std::chrono::duration<double>(config_.segment_await_s)));
  }
  runner_->set_lateness_histogram(lateness_);
  return runner_->run(commands, stop, max_ticks);
}

runlog::WriteStatus Gateway::finish_log() {
  if (!drain_) return runlog::WriteStatus::ok;
  drain_->stop();
  return drain_->last_error();
}

std::uint64_t Gateway::rows_logged() const noexcept {
  return drain_ ? drain_->rows_written() : 0;
}

std::string Gateway::log_failure() const {
  return drain_ ? drain_->failure() : std::string();
}

hal::Nanoseconds Gateway::quiet_interval(bool lockstep) const {
  const hal::Nanoseconds margin = std::chrono::milliseconds(100);
  return lockstep ? margin : period_ + margin;
}

std::string Gateway::foreign_write_report() const {
  const engine::ForeignWrite& f = engine_->foreign_write();
  if (!f.valid) return "";
  const std::string value =
      f.value >= 0 ? config_.values[static_cast<std::size_t>(f.value)].name : std::string("?");
  const std::string why =
      " (another master writes this gateway's registers: one gateway owns a register block, "
      "firmware/app/README.md \"One owner of a register block\")";
  if (f.at_arm) {
    const std::string seconds =
        config::format_number(std::chrono::duration<double>(quiet_interval_).count());
    const std::string what =
        f.heartbeat ? "the heartbeat echo " + value
                    : "setpoint " + config_.setpoints[f.input].name + "'s readback " + value;
    return "another master is writing: " + what + " = " + config::format_number(f.expected) +
           " then " + config::format_number(f.read) + " in two reads " + seconds +
           " s apart before arm, expected unchanged: this gateway wrote nothing" + why;
  }
  const std::string at = " at tick " + std::to_string(f.tick);
  if (f.heartbeat) {
    return "another writer was seen: heartbeat echo " + value + " = " +
           config::format_number(f.read) + at +
           ", expected a heartbeat this gateway sent (the last " +
           config::format_number(f.expected) + ", an echo only moves forward)" + why;
  }
  const std::string where =
      config_.transport
          ? " (" + config_.transport->describe_channel(hal::ChannelKind::setpoint, f.input) + ")"
          : std::string();
  return "another writer was seen: setpoint " + config_.setpoints[f.input].name + where + " = " +
         config::format_number(f.read) + " read back from " + value + at + ", expected " +
         config::format_number(f.expected) +
         " (a value this gateway wrote; or the device rewrote its own setpoint register)" + why;
}

std::string Gateway::readback_fault_report() const {
  const engine::ReadbackFault& f = engine_->readback_fault();
  if (!f.valid) return "";
  const std::string where =
      config_.transport
          ? " (" + config_.transport->describe_channel(hal::ChannelKind::setpoint, f.input) + ")"
          : std::string();
  const auto& sp = config_.setpoints[f.input];
  const std::string readback =
      f.value >= 0 ? config_.values[static_cast<std::size_t>(f.value)].name : sp.readback;
  const engine::InputLimits& in = engine_config_.input[f.input];
  return "setpoint " + sp.name + where + ": wrote " + config::format_number(f.written) +
         ", read back " + config::format_number(f.read) + " from " + readback +
         (f.at_arm ? std::string(" at arm") : " at tick " + std::to_string(f.tick)) +
         " (tolerance " +
         config::format_number(in.readback_abs_tol + in.readback_rel_tol * std::abs(f.written)) +
         ")";
}

std::string Gateway::refusal_report() const {
  if (!runner_ || !runner_->refusal().valid) return "";
  const Refusal& r = runner_->refusal();
  const hal::PeerRefusal& e = r.peer;
  const std::string what(e.reason.data());
  const std::string request(e.request.data());
  const std::string at = " at tick " + std::to_string(r.tick);
  if (!e.write) return "device refused the read of " + request + at + ": " + what;
  std::string named;
  int n = 0;
  for (std::size_t c = 0; c < config_.setpoints.size() && c < hal::kMaxRefusalSetpoints; ++c) {
    if (((e.setpoints >> c) & 1U) == 0) continue;
    const std::string where =
        config_.transport
            ? " (" + config_.transport->describe_channel(hal::ChannelKind::setpoint, c) + ")"
            : std::string();
    named += (n++ == 0 ? "" : ", ") + config_.setpoints[c].name + " = " +
             config::format_number(r.setpoint[c]) + where;
  }
  if (n == 0) return "device refused the write of " + request + at + ": " + what;
  if (n == 1) return "device refused setpoint " + named + at + ": " + what;
  return "device refused setpoints " + named + ", written in one request (" + request + ")" + at +
         ": " + what;
}

std::string Gateway::range_end_report() const {
  std::string out;
  for (std::size_t j = 0; j < config_.values.size(); ++j) {
    if (range_end_counts_[j] == 0) continue;
    out += (out.empty() ? "" : "; ") + config_.values[j].name + " " +
           std::to_string(range_end_counts_[j]) + " readings (" + range_what_[j] + ")";
  }
  return out;
}

}  // namespace excite::app
