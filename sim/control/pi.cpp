// SPDX-License-Identifier: MIT
#include "sim/control/pi.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"
#include "base/config/error.hpp"

namespace excite::sim::control {
namespace {

[[noreturn]] void refuse(const std::string& field, double value, const std::string& expected) {
  throw config::Error(field, config::format_number(value), expected);
}

}  // namespace

PiController::PiController(PiSettings settings) : settings_(std::move(settings)) {
  const PiSettings& s = settings_;
  if (!(std::isfinite(s.sample_time_min) && s.sample_time_min > 0.0)) {
    refuse("sample_time_min", s.sample_time_min, "a finite number of minutes > 0");
  }
  if (s.inputs < 1) refuse("inputs", s.inputs, "at least one MV");
  if (s.outputs < 1) refuse("outputs", s.outputs, "at least one CV");
  if (s.mv.size() != static_cast<std::size_t>(s.inputs)) {
    refuse("mv", static_cast<double>(s.mv.size()), std::to_string(s.inputs) + " MV entries");
  }
  for (std::size_t j = 0; j < s.mv.size(); ++j) {
    const MvSettings& m = s.mv[j];
    const std::string at = "mv[" + std::to_string(j) + "].";
    if (std::isnan(m.min) || m.min == kUnlimited) refuse(at + "min", m.min, "a number below max");
    if (std::isnan(m.max) || !(m.min < m.max)) {
      refuse(at + "max", m.max, "a number above min (" + config::format_number(m.min) + ")");
    }
    if (!(m.max_move > 0.0)) refuse(at + "max_move", m.max_move, "a move > 0");
  }
  if (s.loops.empty()) refuse("pairing", 0, "at least one [[pairing]]");
  std::vector<bool> cv_used(static_cast<std::size_t>(s.outputs)),
      mv_used(static_cast<std::size_t>(s.inputs));
  for (std::size_t i = 0; i < s.loops.size(); ++i) {
    const PiLoop& l = s.loops[i];
    const std::string at = "pairing[" + std::to_string(i) + "].";
    if (l.cv < 0 || l.cv >= s.outputs) {
      refuse(at + "cv", l.cv + 1, "a CV 1.." + std::to_string(s.outputs));
    }
    if (l.mv < 0 || l.mv >= s.inputs) {
      refuse(at + "mv", l.mv + 1, "an MV 1.." + std::to_string(s.inputs));
    }
    if (cv_used[static_cast<std::size_t>(l.cv)]) {
      refuse(at + "cv", l.cv + 1, "a CV in no other pairing");
    }
    if (mv_used[static_cast<std::size_t>(l.mv)]) {
      refuse(at + "mv", l.mv + 1, "an MV in no other pairing");
    }
    cv_used[static_cast<std::size_t>(l.cv)] = true;
    mv_used[static_cast<std::size_t>(l.mv)] = true;
    if (!(std::isfinite(l.gain) && l.gain != 0.0))
      refuse(at + "kc", l.gain, "a finite gain other than 0");
    if (!(std::isfinite(l.integral_min) && l.integral_min > 0.0)) {
      refuse(at + "ti_min", l.integral_min, "a finite integral time > 0 minutes");
    }
  }
  error_prev_.assign(s.loops.size(), 0.0);
  u_prev_.assign(static_cast<std::size_t>(s.inputs), 0.0);
  status_.assign(static_cast<std::size_t>(s.inputs), MvStatus::ok);
}

void PiController::reset() noexcept {
  std::fill(error_prev_.begin(), error_prev_.end(), 0.0);
  std::fill(u_prev_.begin(), u_prev_.end(), 0.0);
  std::fill(status_.begin(), status_.end(), MvStatus::ok);
}

StepReport PiController::step(std::span<const double> y, std::span<const double> y_sp,
                              std::span<const double> known_offsets,
                              std::span<double> u_ctrl) noexcept {
  const auto n = static_cast<std::size_t>(settings_.inputs);
  const auto p = static_cast<std::size_t>(settings_.outputs);
  StepReport report;
  const auto all_finite = [](std::span<const double> v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (y.size() != p || y_sp.size() != p || known_offsets.size() != n || u_ctrl.size() != n ||
      !all_finite(y) || !all_finite(y_sp) || !all_finite(known_offsets)) {
    if (u_ctrl.size() == n) std::copy(u_prev_.begin(), u_prev_.end(), u_ctrl.begin());
    report.status = StepStatus::held;
    return report;
  }
  const double T = settings_.sample_time_min;
  for (std::size_t m = 0; m < n; ++m) status_[m] = MvStatus::ok;
  for (std::size_t i = 0; i < settings_.loops.size(); ++i) {
    const PiLoop& l = settings_.loops[i];
    const auto c = static_cast<std::size_t>(l.cv);
    const auto m = static_cast<std::size_t>(l.mv);
    const MvSettings& mv = settings_.mv[m];
    const double e = y_sp[c] - y[c];
    double du = l.gain * ((e - error_prev_[i]) + (T / l.integral_min) * e);
    error_prev_[i] = e;
    MvStatus status = MvStatus::ok;
    if (std::abs(du) > mv.max_move) {
      du = std::copysign(mv.max_move, du);
      status = MvStatus::move_limited;
    }
    double applied = u_prev_[m] + du + known_offsets[m];
    if (applied <= mv.min) {
      applied = mv.min;
      status = MvStatus::clamped_low;
    } else if (applied >= mv.max) {
      applied = mv.max;
      status = MvStatus::clamped_high;
    }
    u_prev_[m] = applied - known_offsets[m];
    status_[m] = status;
  }
  std::copy(u_prev_.begin(), u_prev_.end(), u_ctrl.begin());
  return report;
}

}  // namespace excite::sim::control
