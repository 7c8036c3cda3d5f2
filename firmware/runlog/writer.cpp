// SPDX-License-Identifier: MIT
#include "firmware/runlog/writer.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <utility>

namespace excite::runlog {
namespace {

// Appends text to a fixed buffer; remembers overflow instead of failing at each call.
class Sink {
 public:
  explicit Sink(std::span<char> out) : out_(out) {}

  void text(std::string_view s) {
    if (overflow_ || s.size() > out_.size() - used_) {
      overflow_ = true;
      return;
    }
    std::memcpy(out_.data() + used_, s.data(), s.size());
    used_ += s.size();
  }
  void ch(char c) { text(std::string_view(&c, 1)); }

  // Shortest round-trip form (std::to_chars without precision).
  void number(double x) {
    if (overflow_) return;
    const auto r = std::to_chars(out_.data() + used_, out_.data() + out_.size(), x);
    if (r.ec != std::errc{}) {
      overflow_ = true;
      return;
    }
    used_ = static_cast<std::size_t>(r.ptr - out_.data());
  }
  void integer(std::uint64_t x) {
    if (overflow_) return;
    const auto r = std::to_chars(out_.data() + used_, out_.data() + out_.size(), x);
    if (r.ec != std::errc{}) {
      overflow_ = true;
      return;
    }
    used_ = static_cast<std::size_t>(r.ptr - out_.data());
  }

  WriteResult result() const {
    if (overflow_) {
      return {WriteStatus::capacity_exceeded, 0,
              "buffer = (too small), expected max_row_chars() or more characters"};
    }
    return {WriteStatus::ok, used_};
  }

 private:
  std::span<char> out_;
  std::size_t used_ = 0;
  bool overflow_ = false;
};

bool one_line(std::string_view s) {
  return s.find('\n') == std::string_view::npos && s.find('\r') == std::string_view::npos;
}

bool channels_valid(const Header& h) {
  const std::span<const Channel> groups[2] = {h.inputs, h.outputs};
  for (const auto& group : groups) {
    for (const Channel& c : group) {
      if (!valid_channel_name(c.name) || !valid_unit(c.unit)) return false;
    }
  }
  // Names are unique over inputs and outputs together (the units line is keyed by name).
  for (std::size_t a = 0; a < h.inputs.size() + h.outputs.size(); ++a) {
    const auto& ca = a < h.inputs.size() ? h.inputs[a] : h.outputs[a - h.inputs.size()];
    for (std::size_t b = a + 1; b < h.inputs.size() + h.outputs.size(); ++b) {
      const auto& cb = b < h.inputs.size() ? h.inputs[b] : h.outputs[b - h.inputs.size()];
      if (ca.name == cb.name) return false;
    }
  }
  return !h.inputs.empty() && !h.outputs.empty();
}

bool all_finite(std::span<const double> xs) {
  for (const double x : xs) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

void column_names(Sink& s, std::string_view prefix, std::span<const Channel> channels) {
  for (const Channel& c : channels) {
    s.ch(',');
    s.text(prefix);
    s.text(c.name);
  }
}

bool closed_loop_valid(const Header& h) {
  const ClosedLoopHeader& c = h.closed_loop;
  if (!c.closed) return true;
  if (c.controller.empty() || !one_line(c.controller) || c.r_channels.empty()) return false;
  const std::size_t side = c.excitation == Excitation::setpoint ? h.outputs.size()
                           : c.excitation == Excitation::mv     ? h.inputs.size()
                                                            : h.outputs.size() + h.inputs.size();
  for (std::size_t i = 0; i < c.r_channels.size(); ++i) {
    if (c.r_channels[i] >= side) return false;
    if (i > 0 && c.r_channels[i] <= c.r_channels[i - 1]) return false;  // ascending, once
  }
  return true;
}

// What is wrong with the header, or null: one line of text per free-text key, a finite
// sample time, time scales ≥ 0, valid unique channels, a valid v4 part.
const char* header_problem(const Header& header) {
  if (!one_line(header.plant) || !one_line(header.plan) || !one_line(header.producer) ||
      !one_line(header.baseline)) {
    return "header.plant/plan/producer/baseline = (a line break), expected one line of text";
  }
  if (!std::isfinite(header.sample_time_min) || header.sample_time_min <= 0.0) {
    return "header.sample_time_min = (not finite or <= 0), expected a finite number > 0";
  }
  const TimeScales& ts = header.time_scales;
  for (const double v : {ts.tau_high_min, ts.beta, ts.switch_time_min}) {
    if (!(std::isfinite(v) && v >= 0.0)) {
      return "header.time_scales = (not finite or < 0), expected finite numbers ≥ 0 (0: not "
             "known)";
    }
  }
  if (!channels_valid(header)) {
    return "header channel = (invalid or repeated), expected a unique name of letters, "
           "digits, _ . - and a unit without spaces, ',' or '='";
  }

  if (!closed_loop_valid(header)) {
    return "header.closed_loop = (no controller text, a line break, or r channels not "
           "ascending on the excitation's side), expected a v4 header (README, Version 4)";
  }
  return nullptr;
}

// The magic line and the '# key: value' lines (README "Format", "Version 4").
void write_header_keys(Sink& s, const Header& header) {
  const ClosedLoopHeader& loop = header.closed_loop;
  const TimeScales& ts = header.time_scales;
  s.text(loop.closed ? kMagicLineV4 : kMagicLine);
  if (!header.producer.empty()) {
    s.text("\n# producer: ");
    s.text(header.producer);
  }
  s.text("\n# plant: ");
  s.text(header.plant);
  s.text("\n# plan: ");
  s.text(header.plan);
  s.text("\n# sample_time_min: ");
  s.number(header.sample_time_min);
  const std::pair<std::string_view, double> scales[] = {
      {"\n# tau_high_min: ", ts.tau_high_min},
      {"\n# beta: ", ts.beta},
      {"\n# switch_time_min: ", ts.switch_time_min}};
  for (const auto& [key, value] : scales) {
    if (value > 0.0) {
      s.text(key);
      s.number(value);
    }
  }
  if (!header.baseline.empty()) {
    s.text("\n# baseline: ");
    s.text(header.baseline);
  }
  if (!header.start_at_rest) s.text("\n# start_at_rest: no");
  if (loop.closed) {
    s.text("\n# loop: closed\n# excitation: ");
    s.text(to_text(loop.excitation));
    s.text("\n# controller: ");
    s.text(loop.controller);
  }
  s.text("\n# inputs:");
  for (const Channel& c : header.inputs) {
    s.ch(' ');
    s.text(c.name);
  }
  s.text("\n# outputs:");
  for (const Channel& c : header.outputs) {
    s.ch(' ');
    s.text(c.name);
  }
  s.text("\n# units:");
  const std::span<const Channel> groups[2] = {header.inputs, header.outputs};
  for (const auto& group : groups) {
    for (const Channel& c : group) {
      s.ch(' ');
      s.text(c.name);
      s.ch('=');
      s.text(c.unit);
    }
  }
}

// The column header row: t_min, k, du_, u_, dy_, in v4 r_, uc_, ysp_, st_, mode; then
// flags, state, segment.
void write_column_row(Sink& s, const Header& header) {
  const ClosedLoopHeader& loop = header.closed_loop;
  s.text("\nt_min,k");
  column_names(s, "du_", header.inputs);
  column_names(s, "u_", header.inputs);
  column_names(s, "dy_", header.outputs);
  if (loop.closed) {
    // `both`: the outputs' r columns, then the inputs' (one index space, outputs first).
    const bool mv = loop.excitation == Excitation::mv;
    for (const std::size_t i : loop.r_channels) {
      s.text(",r_");
      s.text(mv                          ? header.inputs[i].name
             : i < header.outputs.size() ? header.outputs[i].name
                                         : header.inputs[i - header.outputs.size()].name);
    }
    column_names(s, "uc_", header.inputs);
    column_names(s, "ysp_", header.outputs);
    column_names(s, "st_", header.inputs);
    s.text(",mode");
  }
  s.text(",flags,state,segment\n");
}

}  // namespace

std::string_view to_text(Excitation excitation) noexcept {
  switch (excitation) {
    case Excitation::setpoint:
      return "setpoint";
    case Excitation::mv:
      return "mv";
    case Excitation::both:
      return "both";
  }
  return "setpoint";
}

bool excitation_from_text(std::string_view text, Excitation& excitation) noexcept {
  if (text == "setpoint") {
    excitation = Excitation::setpoint;
  } else if (text == "mv") {
    excitation = Excitation::mv;
  } else if (text == "both") {
    excitation = Excitation::both;
  } else {
    return false;
  }
  return true;
}

std::string_view to_text(LoopMode mode) noexcept {
  switch (mode) {
    case LoopMode::off:
      return "off";
    case LoopMode::control:
      return "control";
    case LoopMode::test:
      return "test";
    case LoopMode::suspended:
      return "suspended";
  }
  return "off";
}

bool loop_mode_from_text(std::string_view text, LoopMode& mode) noexcept {
  for (const LoopMode m : {LoopMode::off, LoopMode::control, LoopMode::test, LoopMode::suspended}) {
    if (to_text(m) == text) {
      mode = m;
      return true;
    }
  }
  return false;
}

std::string_view to_text(RunState state) noexcept {
  switch (state) {
    case RunState::unknown:
      return "unknown";
    case RunState::configured:
      return "configured";
    case RunState::armed:
      return "armed";
    case RunState::running:
      return "running";
    case RunState::suspended:
      return "suspended";
    case RunState::completed:
      return "completed";
    case RunState::aborted:
      return "aborted";
    case RunState::returning:
      return "returning";
    case RunState::safe:
      return "safe";
    case RunState::safe_unconfirmed:
      return "safe_unconfirmed";
  }
  return "unknown";
}

bool run_state_from_text(std::string_view text, RunState& state) noexcept {
  for (std::size_t i = 0; i < kRunStateCount; ++i) {
    const auto candidate = static_cast<RunState>(i);
    if (to_text(candidate) == text) {
      state = candidate;
      return true;
    }
  }
  return false;
}

bool valid_channel_name(std::string_view name) {
  if (name.empty()) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

bool valid_unit(std::string_view unit) {
  if (unit.empty()) return false;
  for (const char c : unit) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',' || c == '=') return false;
  }
  return true;
}

std::string_view describe(WriteStatus status) {
  switch (status) {
    case WriteStatus::ok:
      return "ok";
    case WriteStatus::capacity_exceeded:
      return "buffer too small for the formatted text";
    case WriteStatus::invalid_field:
      return "header field invalid (plant/plan text with a line break, a channel name or unit "
             "invalid or repeated, or sample_time_min not finite and > 0)";
    case WriteStatus::bad_argument:
      return "row invalid (width differs from the header's channels, NaN or inf, or unknown "
             "flag bits)";
    case WriteStatus::io_error:
      return "write to the log file failed";
    default:
      return excite::to_string(status);
  }
}

WriteResult format_header(const Header& header, std::span<char> out) {
  if (const char* problem = header_problem(header)) {
    return {WriteStatus::invalid_field, 0, problem};
  }
  Sink s(out);
  write_header_keys(s, header);
  write_column_row(s, header);
  return s.result();
}

WriteResult format_row(const Header& header, const Row& row, std::span<char> out) {
  if (row.du.size() != header.inputs.size() || row.u.size() != header.inputs.size() ||
      row.dy.size() != header.outputs.size()) {
    return {WriteStatus::bad_argument, 0,
            "row du/u/dy = (wrong width), expected the header's channel counts"};
  }
  if (!std::isfinite(row.t_min) || !all_finite(row.du) || !all_finite(row.u) ||
      !all_finite(row.dy)) {
    return {WriteStatus::bad_argument, 0, "row = (NaN or inf), expected finite numbers"};
  }
  const ClosedLoopHeader& loop = header.closed_loop;
  if (loop.closed) {
    if (row.r.size() != loop.r_channels.size() || row.uc.size() != header.inputs.size() ||
        row.ysp.size() != header.outputs.size() || row.st.size() != header.inputs.size()) {
      return {WriteStatus::bad_argument, 0,
              "row r/uc/ysp/st = (wrong width), expected the header's r channels, inputs, "
              "outputs, inputs"};
    }
    if (!all_finite(row.r) || !all_finite(row.uc) || !all_finite(row.ysp)) {
      return {WriteStatus::bad_argument, 0, "row r/uc/ysp = (NaN or inf), expected finite numbers"};
    }
    for (const MvState st : row.st) {
      if (static_cast<std::uint8_t>(st) > kMaxMvState) {
        return {WriteStatus::bad_argument, 0, "row.st = (out of range), expected 0..4"};
      }
    }
    if (static_cast<std::uint8_t>(row.mode) > static_cast<std::uint8_t>(LoopMode::suspended)) {
      return {WriteStatus::bad_argument, 0, "row.mode = (out of range), expected a LoopMode"};
    }
  }
  if ((row.flags & ~kKnownFlags) != 0U) {
    return {WriteStatus::bad_argument, 0, "row.flags = (unknown bits), expected bits of Flag only"};
  }
  if (static_cast<std::size_t>(row.state) >= kRunStateCount) {
    return {WriteStatus::bad_argument, 0, "row.state = (out of range), expected a RunState value"};
  }

  Sink s(out);
  s.number(row.t_min);
  s.ch(',');
  s.integer(row.k);
  const std::span<const double> groups[3] = {row.du, row.u, row.dy};
  for (const auto& group : groups) {
    for (const double x : group) {
      s.ch(',');
      s.number(x);
    }
  }
  if (loop.closed) {
    const std::span<const double> cl[3] = {row.r, row.uc, row.ysp};
    for (const auto& group : cl) {
      for (const double x : group) {
        s.ch(',');
        s.number(x);
      }
    }
    for (const MvState st : row.st) {
      s.ch(',');
      s.integer(static_cast<std::uint8_t>(st));
    }
    s.ch(',');
    s.text(to_text(row.mode));
  }
  s.ch(',');
  s.integer(row.flags);
  s.ch(',');
  s.text(to_text(row.state));
  s.ch(',');
  s.integer(row.segment);
  s.ch('\n');
  return s.result();
}

WriteStatus FileWriter::emit(WriteResult result) {
  detail_ = result.message;
  if (result.status != WriteStatus::ok) return result.status;
  if (std::fwrite(buffer_.data(), 1, result.length, file_) != result.length) {
    detail_ = "log file = (fwrite failed), expected every character written";
    return WriteStatus::io_error;
  }
  return WriteStatus::ok;
}

WriteStatus FileWriter::write_header() {
  return emit(format_header(header_, buffer_));
}

WriteStatus FileWriter::write_row(const Row& row) {
  return emit(format_row(header_, row, buffer_));
}

}  // namespace excite::runlog
