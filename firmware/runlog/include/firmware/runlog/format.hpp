// SPDX-License-Identifier: MIT
#pragma once
// The run log (CSV), version 3: the one format written by the gateway's log thread, by
// `excite simulate` and by `excite-plant`, and read by every downstream tool (identify,
// validate, balance, import). The format is defined in firmware/runlog/README.md; this
// header holds its constants. Writers write v3 only; the reader reads v1, v2 and v3.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace excite::runlog {

/// The first line of every log this code writes (v3), and of the logs written before v3.
inline constexpr std::string_view kMagicLine = "# excite run log v3";
inline constexpr std::string_view kMagicLineV2 = "# excite run log v2";
/// The first line of a closed-loop run's log (v4 = v3 plus the closed-loop header keys and
/// columns, README "Version 4"). Written only for a closed-loop run: an open-loop run's log
/// stays v3, byte for byte.
inline constexpr std::string_view kMagicLineV4 = "# excite run log v4";
inline constexpr std::string_view kMagicLineV1 = "# excite run log v1";

/// The project's version, for the `# producer:` header line ("excite-gateway 0.1.0",
/// "excite simulate 0.1.0"). The line is an optional v1 header key: readers that predate
/// it ignore it (unknown keys are for people), so the format stays version 1.
inline constexpr std::string_view kVersion = EXCITE_VERSION;

/// Per-sample condition bits of the `flags` column (decimal unsigned integer).
enum Flag : std::uint32_t {
  kSuspended = 1U << 0,    // experiment suspended: the engine holds inputs at the baseline
  kCommLost = 1U << 1,     // field-bus reply missing; dy repeats the last good value
  kClamped = 1U << 2,      // at least one input was clamped to its absolute limit
  kRateLimited = 1U << 3,  // at least one input move was limited by its rate limit
  kStale = 1U << 4,        // a process value was older than one sample time
  // New in format v2 (a v1 log carrying them is rejected):
  kSkipped = 1U << 5,        // the clock skipped ticks before this row (wall-clock overrun):
                             // k and t_min jump by the number of ticks missed + 1
  kDiscontinuity = 1U << 6,  // the plant restarted or its time jumped: a new segment starts here
  kBadValue = 1U << 7,       // a value is missing or bad at its source (historian gap, bad quality)
};
/// The flags a v1 log may carry, and those of v2 (what the writer accepts).
inline constexpr std::uint32_t kKnownFlagsV1 =
    kSuspended | kCommLost | kClamped | kRateLimited | kStale;
inline constexpr std::uint32_t kKnownFlags = kKnownFlagsV1 | kSkipped | kDiscontinuity | kBadValue;

/// The `state` column (v2): the gateway engine's lifecycle state when the row was written
/// (firmware/engine/state.hpp has the same states and their meaning). `unknown` when the
/// producer does not know it (the plant's own log: the plant cannot see the gateway's
/// state) and for every row of a v1 log, which has no state column.
enum class RunState : std::uint8_t {
  unknown,
  configured,
  armed,
  running,
  suspended,
  completed,
  aborted,
  returning,
  safe,
  safe_unconfirmed,
};
inline constexpr std::size_t kRunStateCount = 10;

/// The column text of a state ("running", "safe_unconfirmed", …); never empty.
std::string_view to_text(RunState state) noexcept;
/// The state whose text is `text`; false when `text` names none.
bool run_state_from_text(std::string_view text, RunState& state) noexcept;

/// The design's time scales, from the plan (firmware/plan, version 3) or given at import:
/// optional header keys `# tau_high_min:`, `# beta:`, `# switch_time_min:`, written when
/// > 0. identify takes its time-constant bound β·τ_H (SPEC §6) from them. 0 = not known.
/// They need no new format version: older readers ignore them like any unknown key.
struct TimeScales {
  double tau_high_min = 0.0;     // τ_H, minutes
  double beta = 0.0;             // β, settling time in units of τ_H
  double switch_time_min = 0.0;  // T_sw of the design's PRBS, minutes
};

/// v4 `# excitation:` — where excite's test signal r was added: to the CV setpoints
/// (`setpoint`; one r column per output it moves) or to the controller's MV output as a
/// dither (`mv`; one r column per input it moves), or to both (`both`: the r columns of the
/// outputs first, then those of the inputs; an r channel index counts the outputs 0 … p − 1,
/// then the inputs p … p + n − 1).
enum class Excitation : std::uint8_t { setpoint, mv, both };
/// v4 `mode` column: the loop's mode at this row. off: the controller is off (open loop);
/// control: the controller runs, no test signal; test: the controller runs and r is added;
/// suspended: the test is suspended (r held at 0), the controller runs.
enum class LoopMode : std::uint8_t { off, control, test, suspended };
/// v4 `st_<input>` column: each MV's status (what a commercial stepper reads). ok; the MV
/// the plant got sits on its lower or upper limit; the slave loop winds up; the MV is in
/// manual (the controller does not move it).
enum class MvState : std::uint8_t {
  ok = 0,
  clamped_low = 1,
  clamped_high = 2,
  windup = 3,
  manual = 4
};
inline constexpr std::uint8_t kMaxMvState = 4;

std::string_view to_text(Excitation excitation) noexcept;
bool excitation_from_text(std::string_view text, Excitation& excitation) noexcept;
std::string_view to_text(LoopMode mode) noexcept;
bool loop_mode_from_text(std::string_view text, LoopMode& mode) noexcept;

/// Longest state text ("safe_unconfirmed").
inline constexpr std::size_t kMaxStateChars = 16;

/// A channel: name (letters, digits, `_`, `.`, `-`; unique over inputs and outputs) and its
/// engineering unit (no white space, `-` for dimensionless), e.g. {"L", "kmol/min"}.
struct Channel {
  std::string_view name;
  std::string_view unit;
};

/// True when `name` is a valid channel name or unit token (non-empty, no white space, no
/// comma, no `=`). Names are further restricted by valid_channel_name().
bool valid_unit(std::string_view unit);
bool valid_channel_name(std::string_view name);

/// Longest text std::to_chars produces for a double in shortest round-trip form
/// ("-2.2250738585072014e-308" is 24 characters).
inline constexpr std::size_t kMaxNumberChars = 24;

/// Buffer size that always holds one formatted data row of n inputs and p outputs,
/// newline included: t_min, k, 2n + p numbers, flags, state, segment (v3), separators.
constexpr std::size_t max_row_chars(std::size_t n_inputs, std::size_t n_outputs) {
  return (4 + 2 * n_inputs + n_outputs) * (kMaxNumberChars + 1) + (kMaxStateChars + 1) + 1;
}

/// Buffer size that always holds one formatted v4 (closed-loop) row: the v3 row plus
/// `r_channels` r values, n uc and p ysp values, n statuses (one digit) and the mode
/// ("suspended", 9 characters), separators included.
constexpr std::size_t max_closed_loop_row_chars(std::size_t n_inputs, std::size_t n_outputs,
                                                std::size_t r_channels) {
  return max_row_chars(n_inputs, n_outputs) +
         (r_channels + n_inputs + n_outputs) * (kMaxNumberChars + 1) + n_inputs * 2 + 10;
}

}  // namespace excite::runlog
