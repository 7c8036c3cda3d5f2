// SPDX-License-Identifier: MIT
#include "firmware/runlog/reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <utility>

#include "firmware/runlog/format.hpp"

namespace excite::runlog {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = s.find(sep, start);
    parts.push_back(trim(s.substr(start, end == std::string_view::npos ? end : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return parts;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

// The header keys every log has, in this order of the checks (README "Header").
constexpr std::string_view kHeaderKeys[6] = {"plant",  "plan",    "sample_time_min",
                                             "inputs", "outputs", "units"};

// Column roles of the data table.
enum class Role : std::uint8_t { t_min, k, du, u, dy, flags, state, segment, r, uc, ysp, st, mode };
struct ColumnRole {
  Role role;
  std::size_t channel;  // for du, u, dy
};

class Parser {
 public:
  Parser(std::string_view text, std::string_view file, const ReadOptions& options)
      : text_(text), options_(options) {
    error_.file = std::string(file);
  }

  ReadResult run() {
    ReadResult result;
    if (parse_header() && parse_columns() && parse_rows() && check_length()) {
      result.log = std::move(log_);
    } else {
      result.error = std::move(error_);
    }
    return result;
  }

 private:
  // Next line (without its newline); false at end of text.
  bool next_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++line_no_;
    return true;
  }

  bool fail(std::size_t column, std::string message) {
    error_.line = line_no_;
    error_.column = column;
    error_.message = std::move(message);
    return false;
  }

  // The header: the magic line, then '# key: value' lines up to the column header row.
  bool parse_header() {
    if (!parse_magic()) return false;
    std::string_view line;
    for (;;) {
      const std::size_t before = pos_;
      if (!next_line(line)) return fail(0, "end of file before the column header row");
      if (line.empty() || line.front() != '#') {
        pos_ = before;  // the column header row: re-read by parse_columns
        --line_no_;
        break;
      }
      const std::string_view body = trim(line.substr(1));
      const std::size_t colon = body.find(':');
      if (colon == std::string_view::npos) continue;  // free comment
      if (!header_line(trim(body.substr(0, colon)), trim(body.substr(colon + 1)))) return false;
    }
    return header_complete();
  }

  // The first line names the format version (v1 to v4).
  bool parse_magic() {
    std::string_view line;
    if (!next_line(line)) {
      return fail(0, "empty file, expected the line '# excite run log v3' (or v2, v1, v4)");
    }
    if (trim(line) == kMagicLineV4) {
      log_.format_version = 4;
    } else if (trim(line) == kMagicLine) {
      log_.format_version = 3;
    } else if (trim(line) == kMagicLineV2) {
      log_.format_version = 2;
    } else if (trim(line) == kMagicLineV1) {
      log_.format_version = 1;
    } else {
      if (line.rfind("# excite run log v", 0) == 0) {
        return fail(0,
                    "unsupported version " + quoted(trim(line)) + "; this reader reads v1 to v4");
      }
      return fail(0,
                  "first line is " + quoted(trim(line)) +
                      ", expected '# excite run log v3' (or v2, v1, v4) (not an excite run log?)");
    }
    return true;
  }

  // One '# key: value' line: a required key (kHeaderKeys, each once) or an optional one.
  bool header_line(std::string_view key, std::string_view value) {
    // Free text is one line; a carriage return inside it is damage the writer never makes.
    if ((key == "plant" || key == "plan" || key == "producer") &&
        value.find('\r') != std::string_view::npos) {
      return fail(0, "header key '" + std::string(key) +
                         "' has a carriage return inside its text, expected one line");
    }
    const auto* required = std::find(std::begin(kHeaderKeys), std::end(kHeaderKeys), key);
    if (required == std::end(kHeaderKeys)) return optional_key(key, value);
    const auto which = static_cast<std::size_t>(required - std::begin(kHeaderKeys));
    if (seen_[which]) return fail(0, "header key '" + std::string(key) + "' given twice");
    seen_[which] = true;
    return required_key(which, value);
  }

  // The time scales, start_at_rest, the v4 keys, baseline, producer; other keys are for
  // people and ignored.
  bool optional_key(std::string_view key, std::string_view value) {
    struct OptionalNumber {  // the optional time scales (TimeScales)
      std::string_view key;
      double* value;
    };
    const OptionalNumber scales[3] = {{"tau_high_min", &log_.time_scales.tau_high_min},
                                      {"beta", &log_.time_scales.beta},
                                      {"switch_time_min", &log_.time_scales.switch_time_min}};
    for (std::size_t i = 0; i < 3; ++i) {
      if (scales[i].key != key) continue;
      if (scale_seen_[i]) return fail(0, "header key '" + std::string(key) + "' given twice");
      scale_seen_[i] = true;
      double& v = *scales[i].value;
      const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
      if (r.ec != std::errc{} || r.ptr != value.data() + value.size() || !std::isfinite(v) ||
          v < 0.0) {
        return fail(0, std::string(key) + " = " + quoted(value) +
                           ", expected a finite number ≥ 0 (0: not known)");
      }
      return true;
    }
    if (key == "start_at_rest") {
      if (value != "yes" && value != "no") {
        return fail(0, "start_at_rest = " + quoted(value) + ", expected yes or no");
      }
      log_.start_at_rest = value == "yes";
      return true;
    }
    if (log_.format_version == 4 && (key == "loop" || key == "excitation" || key == "controller")) {
      return closed_key(key, value);
    }
    if (key == "baseline") {
      log_.baseline = std::string(value);
    } else if (key == "producer") {  // optional: logs written before it existed have none
      if (seen_producer_) return fail(0, "header key 'producer' given twice");
      seen_producer_ = true;
      log_.producer = std::string(value);
    }
    return true;
  }

  // plant, plan, sample_time_min, inputs, outputs, units (kHeaderKeys[which]).
  bool required_key(std::size_t which, std::string_view value) {
    switch (which) {
      case 0:
        log_.plant = std::string(value);
        return true;
      case 1:
        log_.plan = std::string(value);
        return true;
      case 2: {
        double t = 0.0;
        const auto r = std::from_chars(value.data(), value.data() + value.size(), t);
        if (r.ec != std::errc{} || r.ptr != value.data() + value.size() || !std::isfinite(t) ||
            t <= 0.0) {
          return fail(0, "sample_time_min is " + quoted(value) +
                             ", expected a finite number > 0 (minutes)");
        }
        log_.sample_time_min = t;
        return true;
      }
      case 3:
      case 4: {
        auto& names = which == 3 ? log_.input_names : log_.output_names;
        for (const auto w : words(value)) {
          if (!valid_channel_name(w)) {
            return fail(0, "channel name " + quoted(w) +
                               " is invalid, expected letters, digits, '_', '.', '-'");
          }
          names.emplace_back(w);
        }
        if (names.empty()) {
          return fail(0, std::string(which == 3 ? "inputs" : "outputs") +
                             " lists no channel, expected at least one name");
        }
        return true;
      }
      default:  // units: read once the channels are known (header_complete)
        units_value_ = value;
        units_line_ = line_no_;
        return true;
    }
  }

  // Every required key given (and in v4 the closed-loop ones), names unique, then the units.
  bool header_complete() {
    for (std::size_t i = 0; i < std::size(kHeaderKeys); ++i) {
      if (!seen_[i]) {
        return fail(0, "header has no '# " + std::string(kHeaderKeys[i]) +
                           ":' line, expected plant, plan, sample_time_min, inputs, outputs, "
                           "units");
      }
    }
    if (log_.format_version == 4) {
      for (const std::string_view key : {"loop", "excitation", "controller"}) {
        if (!closed_seen_[key == "loop" ? 0 : key == "excitation" ? 1 : 2]) {
          return fail(0, "header has no '# " + std::string(key) +
                             ":' line, expected loop, excitation and controller in a v4 log");
        }
      }
      log_.closed_loop.closed = true;
    }
    // Names unique over inputs and outputs.
    std::vector<std::string> all = log_.input_names;
    all.insert(all.end(), log_.output_names.begin(), log_.output_names.end());
    for (std::size_t a = 0; a < all.size(); ++a) {
      for (std::size_t b = a + 1; b < all.size(); ++b) {
        if (all[a] == all[b]) {
          return fail(0, "channel name " + quoted(all[a]) + " is used twice; names must be unique");
        }
      }
    }
    return parse_units(units_value_, units_line_, all);
  }

  // The v4 header keys (README "Version 4"): each once.
  bool closed_key(std::string_view key, std::string_view value) {
    const std::size_t which = key == "loop" ? 0 : key == "excitation" ? 1 : 2;
    if (closed_seen_[which]) return fail(0, "header key '" + std::string(key) + "' given twice");
    closed_seen_[which] = true;
    if (which == 0 && value != "closed") {
      return fail(0,
                  "loop = " + quoted(value) + ", expected closed (a v4 log is a closed-loop run)");
    }
    if (which == 1 && !excitation_from_text(value, log_.closed_loop.excitation)) {
      return fail(0, "excitation = " + quoted(value) + ", expected setpoint, mv or both");
    }
    if (which == 2) {
      if (value.empty()) return fail(0, "controller = '', expected its kind and a description");
      log_.closed_loop.controller = std::string(value);
    }
    return true;
  }

  bool parse_units(std::string_view value, std::size_t at_line,
                   const std::vector<std::string>& all) {
    std::vector<std::string> units(all.size());
    for (const auto w : words(value)) {
      const std::size_t eq = w.find('=');
      const std::string_view name = w.substr(0, eq);
      const std::string_view unit = eq == std::string_view::npos ? "" : w.substr(eq + 1);
      std::size_t idx = all.size();
      for (std::size_t i = 0; i < all.size(); ++i) {
        if (all[i] == name) idx = i;
      }
      if (eq == std::string_view::npos || !valid_unit(unit)) {
        line_no_ = at_line;
        return fail(0, "units entry " + quoted(w) + " is not of the form name=unit");
      }
      if (idx == all.size()) {
        line_no_ = at_line;
        return fail(0, "units entry " + quoted(w) + " names no declared channel");
      }
      units[idx] = std::string(unit);
    }
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (units[i].empty()) {
        line_no_ = at_line;
        return fail(0, "units line gives no unit for channel " + quoted(all[i]) + ", expected " +
                           all[i] + "=<unit> ('-' if dimensionless)");
      }
    }
    const std::size_t n = log_.input_names.size();
    log_.input_units.assign(units.begin(), units.begin() + static_cast<std::ptrdiff_t>(n));
    log_.output_units.assign(units.begin() + static_cast<std::ptrdiff_t>(n), units.end());
    return true;
  }

  // The columns the header implies, with their roles; the row may list them in any order.
  using ExpectedColumns = std::vector<std::pair<std::string, ColumnRole>>;
  ExpectedColumns expected_columns() const {
    const std::size_t n = log_.input_names.size();
    const std::size_t p = log_.output_names.size();
    ExpectedColumns expected;
    expected.push_back({"t_min", {Role::t_min, 0}});
    expected.push_back({"k", {Role::k, 0}});
    for (std::size_t i = 0; i < n; ++i) {
      expected.push_back({"du_" + log_.input_names[i], {Role::du, i}});
    }
    for (std::size_t i = 0; i < n; ++i) {
      expected.push_back({"u_" + log_.input_names[i], {Role::u, i}});
    }
    for (std::size_t j = 0; j < p; ++j) {
      expected.push_back({"dy_" + log_.output_names[j], {Role::dy, j}});
    }
    const ClosedLoopLog& cl = log_.closed_loop;
    if (cl.closed) {
      // r channel indices: outputs for setpoint, inputs for mv; both: outputs 0 … p − 1,
      // then the inputs p … p + n − 1 (README "Version 4").
      const bool sp = cl.excitation != Excitation::mv;
      const bool mv = cl.excitation != Excitation::setpoint;
      for (std::size_t j = 0; sp && j < p; ++j) {
        expected.push_back({"r_" + log_.output_names[j], {Role::r, j}});
      }
      const std::size_t first_input = cl.excitation == Excitation::both ? p : 0;
      for (std::size_t i = 0; mv && i < n; ++i) {
        expected.push_back({"r_" + log_.input_names[i], {Role::r, first_input + i}});
      }
      for (std::size_t i = 0; i < n; ++i) {
        expected.push_back({"uc_" + log_.input_names[i], {Role::uc, i}});
      }
      for (std::size_t j = 0; j < p; ++j) {
        expected.push_back({"ysp_" + log_.output_names[j], {Role::ysp, j}});
      }
      for (std::size_t i = 0; i < n; ++i) {
        expected.push_back({"st_" + log_.input_names[i], {Role::st, i}});
      }
      expected.push_back({"mode", {Role::mode, 0}});
    }
    expected.push_back({"flags", {Role::flags, 0}});
    if (log_.format_version >= 2) expected.push_back({"state", {Role::state, 0}});
    if (log_.format_version >= 3) expected.push_back({"segment", {Role::segment, 0}});
    return expected;
  }

  // v4: the r columns present (at least one), each mapped to its place in r_channels
  // (ascending by channel); the closed-loop series sized.
  bool index_r_columns(const ExpectedColumns& expected, const std::vector<bool>& found) {
    ClosedLoopLog& cl = log_.closed_loop;
    const std::size_t n = log_.input_names.size();
    const std::size_t p = log_.output_names.size();
    std::vector<std::size_t> slot(expected.size(), 0);
    for (std::size_t e = 0; e < expected.size(); ++e) {
      if (found[e] && expected[e].second.role == Role::r) {
        slot[e] = cl.r_channels.size();
        cl.r_channels.push_back(expected[e].second.channel);
      }
    }
    if (cl.r_channels.empty()) {
      return fail(0, std::string("r columns = (none), expected r_<") +
                         (cl.excitation == Excitation::setpoint ? "output"
                          : cl.excitation == Excitation::mv     ? "input"
                                                                : "output or input") +
                         "> for each channel the excitation moves");
    }
    // Each r column's channel → its place in r_channels (ascending by channel).
    for (ColumnRole& role : roles_) {
      if (role.role != Role::r) continue;
      for (std::size_t e = 0; e < expected.size(); ++e) {
        if (expected[e].second.role == Role::r && expected[e].second.channel == role.channel) {
          role.channel = slot[e];
          break;
        }
      }
    }
    cl.r.assign(cl.r_channels.size(), {});
    cl.uc.assign(n, {});
    cl.ysp.assign(p, {});
    cl.st.assign(n, {});
    return true;
  }

  bool parse_columns() {
    std::string_view line;
    if (!next_line(line)) return fail(0, "end of file, expected the column header row");
    const auto names = split(line, ',');
    const ExpectedColumns expected = expected_columns();
    std::vector<bool> found(expected.size(), false);
    for (std::size_t c = 0; c < names.size(); ++c) {
      std::size_t idx = expected.size();
      for (std::size_t e = 0; e < expected.size(); ++e) {
        if (expected[e].first == names[c]) idx = e;
      }
      if (idx == expected.size()) {
        return fail(c + 1, "unexpected column " + quoted(names[c]) +
                               " (not derived from the header's inputs/outputs)");
      }
      if (found[idx]) return fail(c + 1, "column " + quoted(names[c]) + " appears twice");
      found[idx] = true;
      roles_.push_back(expected[idx].second);
      column_names_.emplace_back(names[c]);
    }
    for (std::size_t e = 0; e < expected.size(); ++e) {
      // r_<channel>: only the channels r was added to (at least one, checked below).
      if (!found[e] && expected[e].second.role != Role::r) {
        return fail(0, "missing column " + quoted(expected[e].first));
      }
    }
    if (log_.closed_loop.closed && !index_r_columns(expected, found)) return false;
    log_.du.assign(log_.input_names.size(), {});
    log_.u.assign(log_.input_names.size(), {});
    log_.dy.assign(log_.output_names.size(), {});
    return true;
  }

  std::string column_label(std::size_t c) const {
    return "column " + std::to_string(c + 1) + " (" + column_names_[c] + ")";
  }

  bool field_error(std::size_t c, std::string_view text, std::string_view expected) {
    error_.line = line_no_;
    error_.column = c + 1;
    error_.message =
        column_names_[c] + " = " + quoted(text) + ", expected " + std::string(expected);
    return false;
  }

  bool parse_rows() {
    std::string_view line;
    while (next_line(line)) {
      if (trim(line).empty()) continue;  // a trailing blank line is tolerated
      if (line.front() == '#') return fail(0, "comment line inside the data, expected a data row");
      const auto fields = split(line, ',');
      if (fields.size() != roles_.size()) {
        return fail(0, std::to_string(fields.size()) + " fields, expected " +
                           std::to_string(roles_.size()) + " as in the column header row");
      }
      for (std::size_t c = 0; c < fields.size(); ++c) {
        if (!parse_field(c, fields[c])) return false;
      }
      if (log_.format_version == 1) log_.state.push_back(RunState::unknown);
      if (log_.format_version <= 2) log_.segment.push_back(0);
      if (!check_time()) return false;
    }
    return true;
  }

  // k, flags and segment: non-negative integers (flags: only the documented bits).
  bool parse_integer_field(std::size_t c, std::string_view f, ColumnRole role) {
    const char* last = f.data() + f.size();
    std::uint64_t v = 0;
    const auto r = std::from_chars(f.data(), last, v);
    if (f.empty() || r.ec != std::errc{} || r.ptr != last) {
      return field_error(c, f, "a non-negative integer");
    }
    if (role.role == Role::segment) {
      if (v > 0xFFFFFFFFU) return field_error(c, f, "a segment id of at most 4294967295");
      log_.segment.push_back(static_cast<std::uint32_t>(v));
    } else if (role.role == Role::k) {
      log_.k.push_back(v);
    } else {
      const bool v1 = log_.format_version == 1;
      if ((v & ~std::uint64_t{v1 ? kKnownFlagsV1 : kKnownFlags}) != 0U) {
        return field_error(c, f,
                           v1 ? "only the documented flag bits (v1: suspended=1, "
                                "comm_lost=2, clamped=4, rate_limited=8, stale=16)"
                              : "only the documented flag bits (suspended=1, "
                                "comm_lost=2, clamped=4, rate_limited=8, stale=16, "
                                "skipped=32, discontinuity=64, bad_value=128)");
      }
      log_.flags.push_back(static_cast<std::uint32_t>(v));
    }
    return true;
  }

  // Every other column: a finite number, kept in its series.
  bool parse_number_field(std::size_t c, std::string_view f, ColumnRole role) {
    const char* last = f.data() + f.size();
    double v = 0.0;
    const auto r = std::from_chars(f.data(), last, v);
    if (f.empty() || r.ec == std::errc::invalid_argument || r.ptr != last) {
      return field_error(c, f, "a number");
    }
    if (r.ec == std::errc::result_out_of_range || !std::isfinite(v)) {
      return field_error(c, f, "a finite number (no NaN or inf in a run log)");
    }
    switch (role.role) {
      case Role::t_min:
        log_.t_min.push_back(v);
        break;
      case Role::du:
        log_.du[role.channel].push_back(v);
        break;
      case Role::u:
        log_.u[role.channel].push_back(v);
        break;
      case Role::dy:
        log_.dy[role.channel].push_back(v);
        break;
      case Role::r:
        log_.closed_loop.r[role.channel].push_back(v);
        break;
      case Role::uc:
        log_.closed_loop.uc[role.channel].push_back(v);
        break;
      case Role::ysp:
        log_.closed_loop.ysp[role.channel].push_back(v);
        break;
      default:
        break;
    }
    return true;
  }

  bool parse_field(std::size_t c, std::string_view f) {
    const ColumnRole role = roles_[c];
    if (role.role == Role::state) {
      RunState state = RunState::unknown;
      if (!run_state_from_text(f, state)) {
        return field_error(c, f,
                           "a run state: unknown, configured, armed, running, suspended, "
                           "completed, aborted, returning, safe or safe_unconfirmed");
      }
      log_.state.push_back(state);
      return true;
    }
    if (role.role == Role::mode) {
      LoopMode mode = LoopMode::off;
      if (!loop_mode_from_text(f, mode)) {
        return field_error(c, f, "a loop mode: off, control, test or suspended");
      }
      log_.closed_loop.mode.push_back(mode);
      return true;
    }
    if (role.role == Role::st) {
      if (f.size() != 1 || f[0] < '0' || f[0] > static_cast<char>('0' + kMaxMvState)) {
        return field_error(c, f,
                           "an MV status: 0 ok, 1 clamped low, 2 clamped high, 3 windup, "
                           "4 manual");
      }
      log_.closed_loop.st[role.channel].push_back(static_cast<MvState>(f[0] - '0'));
      return true;
    }
    if (role.role == Role::k || role.role == Role::flags || role.role == Role::segment) {
      return parse_integer_field(c, f, role);
    }
    return parse_number_field(c, f, role);
  }

  std::size_t column_of(Role role) const {
    for (std::size_t c = 0; c < roles_.size(); ++c) {
      if (roles_[c].role == role) return c + 1;
    }
    return 0;
  }

  // Uniform time (README "Rules the reader checks"): one tick per row, except after
  // skipped ticks (v2, kSkipped), where k and t_min jump together by the ticks missed.
  bool check_time() {
    const std::size_t r = log_.t_min.size() - 1;
    if (r == 0) return true;
    const bool skipped = log_.format_version >= 2 && (log_.flags[r] & kSkipped) != 0U;
    if (skipped ? log_.k[r] <= log_.k[r - 1] + 1 : log_.k[r] != log_.k[r - 1] + 1) {
      return fail(column_of(Role::k), "k: " + std::to_string(log_.k[r]) + " follows " +
                                          std::to_string(log_.k[r - 1]) +
                                          (skipped ? ", expected more than " : ", expected ") +
                                          std::to_string(log_.k[r - 1] + 1) +
                                          (skipped ? " (the row is flagged skipped)" : ""));
    }
    const double T = log_.sample_time_min;
    const auto ticks = static_cast<double>(log_.k[r] - log_.k[r - 1]);
    const double dt = log_.t_min[r] - log_.t_min[r - 1];
    if (std::abs(dt - ticks * T) > options_.time_tolerance * T) {
      char buf[240];
      if (ticks == 1.0) {
        std::snprintf(buf, sizeof buf,
                      "t_min: step %.17g min from the previous row, expected the sample time "
                      "%.17g min (tolerance %.3g of it)",
                      dt, T, options_.time_tolerance);
      } else {
        std::snprintf(buf, sizeof buf,
                      "t_min: step %.17g min from the previous row, expected %.17g min (%.17g "
                      "ticks of the sample time %.17g min, tolerance %.3g of it)",
                      dt, ticks * T, ticks, T, options_.time_tolerance);
      }
      return fail(column_of(Role::t_min), buf);
    }
    return true;
  }

  bool check_length() {
    if (log_.rows() < options_.min_rows) {
      return fail(0, std::to_string(log_.rows()) + " data rows, expected at least " +
                         std::to_string(options_.min_rows));
    }
    return true;
  }

  std::string_view text_;
  ReadOptions options_;
  std::size_t pos_ = 0;
  std::size_t line_no_ = 0;
  RunLog log_;
  ReadError error_;
  std::vector<ColumnRole> roles_;
  bool closed_seen_[3] = {};  // v4: loop, excitation, controller
  // The header's keys seen (kHeaderKeys; the time scales; producer) and the units line,
  // read once the channels are known.
  bool seen_[6] = {};
  bool scale_seen_[3] = {};
  bool seen_producer_ = false;
  std::string_view units_value_;
  std::size_t units_line_ = 0;
  std::vector<std::string> column_names_;
};

// Data rows (lines neither blank nor `#` comments, less the column header row) counted in
// chunks as they arrive, in fixed memory.
class RowCounter {
 public:
  void add(std::string_view chunk) {
    for (const char c : chunk) {
      if (at_line_start_ && c != '#' && c != '\n' && c != '\r') ++lines_;
      at_line_start_ = c == '\n';
    }
  }
  std::size_t data_rows() const { return lines_ == 0 ? 0 : lines_ - 1; }

 private:
  std::size_t lines_ = 0;
  bool at_line_start_ = true;
};

ReadResult refused(std::string_view file, std::string message) {
  ReadResult r;
  r.error = ReadError{std::string(file), 0, 0, std::move(message)};
  return r;
}

ReadResult over_row_limit(std::string_view file, const ReadOptions& options) {
  const std::string n = std::to_string(options.max_rows);
  ReadResult r = refused(
      file,
      "more than " + n + " data rows, expected at most " + n +
          (options.limits_source.empty() ? std::string() : " (" + options.limits_source + ")"));
  r.over_row_limit = true;
  return r;
}

// The first du or dy value beyond ±max_abs_value, column by column (inputs first).
ReadResult check_values(ReadResult read, std::string_view file, const ReadOptions& options) {
  if (!read.ok() || options.max_abs_value <= 0.0) return read;
  const RunLog& log = read.log;
  const auto check = [&](const std::vector<std::vector<double>>& columns,
                         const std::vector<std::string>& names,
                         const char* prefix) -> std::optional<ReadResult> {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      for (std::size_t r = 0; r < columns[c].size(); ++r) {
        const double v = columns[c][r];
        if (std::fabs(v) <= options.max_abs_value) continue;
        char text[160];
        std::snprintf(text, sizeof text, "data row %zu (k = %llu), column %s", r + 1,
                      static_cast<unsigned long long>(log.k[r]), prefix);
        char value[80];
        std::snprintf(value, sizeof value, " = %.6g, expected |value| <= %g", v,
                      options.max_abs_value);
        return refused(file, text + names[c] + value);
      }
    }
    return std::nullopt;
  };
  if (auto bad = check(log.du, log.input_names, "du_")) return std::move(*bad);
  if (auto bad = check(log.dy, log.output_names, "dy_")) return std::move(*bad);
  return read;
}

}  // namespace

std::string ReadError::to_string() const {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  s += ": ";
  if (column > 0) s += "column " + std::to_string(column) + ": ";
  return s + message;
}

ReadResult parse_run_log(std::string_view text, std::string_view file_name,
                         const ReadOptions& options) {
  RowCounter rows;
  rows.add(text);
  if (rows.data_rows() > options.max_rows) return over_row_limit(file_name, options);
  return check_values(Parser(text, file_name, options).run(), file_name, options);
}

ReadResult read_run_log(const std::string& path, const ReadOptions& options) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    ReadResult r;
    r.error = ReadError{path, 0, 0, "cannot open the file for reading"};
    return r;
  }
  std::string text;
  char buf[65536];
  std::size_t got = 0;
  RowCounter rows;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) {
    rows.add(std::string_view(buf, got));
    if (rows.data_rows() > options.max_rows) {
      std::fclose(f);
      return over_row_limit(path, options);
    }
    text.append(buf, got);
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) {
    ReadResult r;
    r.error = ReadError{path, 0, 0, "read error"};
    return r;
  }
  return parse_run_log(text, path, options);
}

}  // namespace excite::runlog
