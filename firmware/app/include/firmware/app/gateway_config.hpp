// SPDX-License-Identifier: MIT
#pragma once
// The gateway configuration file (TOML; README.md has the complete example): run
// parameters in seconds, the transport named by [device] transport, which reads its own
// part of the file (hal's transport seam: excite/hal/transport.hpp, the table of them in
// hal/transports), and per setpoint and per value what the engine needs (absolute limits,
// slew, readback, test limits, roles). Parsed once at start-up (allocates); every error
// names the file, the key, the value found and what was expected.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "excite/hal/transport.hpp"
#include "firmware/app/timing_range.hpp"
#include "firmware/engine/config.hpp"
#include "firmware/plan/plan.hpp"

namespace excite::app {

/// What a value read from the field is for.
enum class ValueRole : std::uint8_t {
  output,          // a controlled variable: logged as dy_<name>, may carry test limits
  readback,        // the live value of a setpoint: the baseline at arm
  heartbeat_echo,  // the peer's echo of the heartbeat counter
  command,         // the operator command register: 1 start, 2 suspend, 3 resume, 4 abort
  // Closed loop only ([closed_loop]; README "Closed loop"), read back as data. The i-th
  // value of a role belongs to the i-th MV (or CV), in the controller's order.
  controller_mode,    // the controller's mode: 0 off, 1 control, 2 test, 3 suspended
  mv_status,          // an MV's status: 0 ok, 1 clamped low, 2 clamped high, 3 windup, 4 manual
  controller_move,    // an MV's controller move (deviation, before the offset and the clamp)
  applied_mv,         // an MV as the plant got it (deviation): data, never a fault
  setpoint_in_force,  // a CV's setpoint in force (deviation)
};

/// A role's key in the file ("readback" for ValueRole::readback), one table for the reader
/// and the writer (gateway_config_writer.hpp).
const char* role_name(ValueRole role) noexcept;
/// The role named `name`, or none.
std::optional<ValueRole> role_of(std::string_view name) noexcept;

/// [closed_loop]: the gateway writes test offsets to a running controller (issue 42 §2).
struct ClosedLoopSpec {
  // Which offsets the setpoints are: "mv" (MV test offsets, a dither added to the
  // controller's output), "setpoint" (CV setpoint offsets) or "both".
  std::string offsets = "setpoint";
  std::string controller;  // the run log's `controller:` line (kind and free text), optional
  // Suspended for the controller (an MV clamped or wound up, the controller out of its
  // mode) this long → aborted; 0: never. 0 … 1e6 s.
  double controller_timeout_s = 60.0;
  // Each MV's operating point (absolute, engineering units), one per mv_status value: the
  // run log's u_<MV> = mv_baseline + the applied MV read back (README "Closed loop", the run
  // log). Empty: u_<MV> is the applied deviation itself (no operating point known).
  std::vector<double> mv_baseline;
};

struct SetpointSpec {
  std::string name;  // run-log channel name: letters, digits, _ . -
  std::string unit = "-";
  double min = 0.0;  // absolute limits of the setpoint, engineering units
  double max = 0.0;
  double max_move = 0.0;  // largest change per tick
  std::string readback;   // name of the value (role readback) giving the baseline
};

struct ValueSpec {
  std::string name;
  std::string unit = "-";
  ValueRole role = ValueRole::output;
  std::optional<double> test_low;  // test limits (outputs), absolute engineering units
  std::optional<double> test_high;
  double hysteresis = 0.0;
  // role command, `acknowledge = "clear"`: after reading a command the gateway writes 0
  // back, so the same code written again is a new command (README "Operator commands").
  bool acknowledge = false;
};

struct GatewayConfig {
  std::string source;               // file name, for messages
  std::string plant = "unnamed";    // the run log's `plant:` line
  std::optional<double> period_s;   // tick period; default the plan's sample time
  double ramp_s = 0.0;              // excitation ramps in and out over this time
  double resume_dwell_s = 0.0;      // back inside the limits this long → resume
  double suspend_timeout_s = 0.0;   // suspended this long → abort; 0 = never
  double confirm_timeout_s = 60.0;  // after an abort or the end: the baseline confirmed (read
                                    // back twice, a hold interval apart) within this, else
                                    // safe, unconfirmed (issue 28 item 2); > 0
  std::uint32_t comm_fail_limit = 3;
  // Verified writes (README.md): the reading of tick k reflects the write of tick
  // k − (readback_lag_ticks − 1) (1: the same exchange, the Runner writes then reads); more
  // than readback_mismatch_limit consecutive mismatching ticks on one setpoint is a fault.
  std::uint32_t readback_lag_ticks = 1;
  std::uint32_t readback_mismatch_limit = 3;
  engine::CommLossAction comm_loss = engine::CommLossAction::hold;
  double heartbeat_max_lag_s = 0.0;  // with a heartbeat_echo value; 0 → 3 ticks
  std::uint32_t log_ring = 4096;     // run-log ring records
  double log_max_mb = 1024.0;        // the run log's size limit (MB = 1e6 bytes): a row beyond
                                     // it is a log fault (exit 13), so a run suspended for hours
                                     // cannot fill a disk; 0.001 … 1e6
  double max_distortion = 0.0;       // largest fraction (0…1) of a channel's rows the engine
                                     // may clamp or rate-limit; more → refused (exit 12)
  int realtime_priority = 80;        // SCHED_FIFO priority; 0 = leave the scheduler alone
  bool simulator = false;            // [device] simulator: the peer is a simulated plant
                                     // (allows --clock lockstep)
  std::optional<double> peer_watchdog_s;  // [device] peer_watchdog_s: the peer's own heartbeat
                                          // watchdog as declared (seconds; 0: none): refused
                                          // when shorter than two tick periods (check_timing)
  // [segments] (README "Plan segments"): an approved segment is taken after a row r of the
  // running table with (r + 1) % segment_period_rows == 0, or after its last row (0: only
  // there); a segment whose plan provenance contains segment_preapproved_from needs no
  // operator approval ("": every segment needs one).
  std::uint32_t segment_period_rows = 0;
  std::string segment_preapproved_from;
  // [segments] await_s: at the running table's end with no approved segment, wait this long
  // for one instead of ending the run (0: end it). Real time: the baseline is held and
  // logged (rows flagged suspended, state running); lock-step: the gateway stops ticking,
  // timed on the real clock. 0 … 1e6 s.
  double segment_await_s = 0.0;
  // [device] transport: its device, sections and per-entry mapping as it read them; null
  // when the bus is handed over built (the in-process tests).
  std::shared_ptr<const hal::TransportConfig> transport;
  std::vector<SetpointSpec> setpoints;        // in plan channel order
  std::vector<ValueSpec> values;              // in register-map order
  std::optional<ClosedLoopSpec> closed_loop;  // [closed_loop]: absent in an open-loop run
};

struct ConfigResult {
  std::optional<GatewayConfig> config;
  std::string error;  // "<source>[:line:col]: <field> = <value>, expected <what>" when !config
};

ConfigResult parse_gateway_config(std::string_view text, std::string_view source);
ConfigResult load_gateway_config(const std::string& path);

// Accepted timing (README "Timing"): kMinPeriodS, kMaxPeriodS, kMaxDurationS
// (timing_range.hpp); converted to ticks of the period, within the engine's range.

/// "" when every duration of `config` converts to ticks of `period` within the engine's
/// ranges; otherwise "<source>: gateway.<key> = <value> (<n> ticks of <p> s), expected …".
/// Call before to_engine_config().
std::string check_timing(const GatewayConfig& config, std::chrono::duration<double> period);

/// The engine's configuration for a tick period (the configuration's seconds → ticks,
/// rounded up, saturating: check_timing() first). Value indices follow the register-map
/// order.
engine::EngineConfig to_engine_config(const GatewayConfig& config,
                                      std::chrono::duration<double> period);

/// What the encoding of each channel of `kind` carries (the transport's carried_range);
/// empty without a transport.
std::vector<hal::CarriedRange> carried_ranges(const GatewayConfig& config, hal::ChannelKind kind);

/// Value indices of the outputs (the run log's dy columns), in order.
std::vector<int> output_indices(const GatewayConfig& config);

/// What the setpoints stream, for engine::load_plan: MV moves (open loop, or [closed_loop]
/// offsets "both": only an open-loop plan, in the setpoints' own order and units), CV
/// setpoint offsets ("setpoint") or MV offsets ("mv").
plan::Excitation streamed_excitation(const GatewayConfig& config);

}  // namespace excite::app
