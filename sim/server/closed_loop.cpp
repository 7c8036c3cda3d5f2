// SPDX-License-Identifier: MIT
#include "sim/server/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace excite::sim::server {

ClosedLoop::ClosedLoop(std::unique_ptr<control::Controller> controller, std::vector<double> mv_min,
                       std::vector<double> mv_max)
    : controller_(std::move(controller)), min_(std::move(mv_min)), max_(std::move(mv_max)) {
  if (!controller_) throw std::invalid_argument("ClosedLoop: no controller");
  const auto n = static_cast<std::size_t>(controller_->inputs());
  const auto m = static_cast<std::size_t>(controller_->outputs());
  if (min_.size() != n || max_.size() != n) {
    throw std::invalid_argument("ClosedLoop: MV limits do not match the controller");
  }
  moves_.assign(n, 0.0);
  applied_.assign(n, 0.0);
  offsets_.assign(n, 0.0);
  zeros_.assign(n, 0.0);
  status_.assign(n, LoopStatus::ok);
  setpoints_.assign(m, 0.0);
  controller_->reset();
}

void ClosedLoop::apply(std::span<const double> offsets) noexcept {
  for (std::size_t i = 0; i < applied_.size(); ++i) {
    const double asked = moves_[i] + offsets[i];
    const double u = std::clamp(asked, min_[i], max_[i]);
    const double tol_lo = 1e-9 * (1.0 + std::abs(min_[i]));
    const double tol_hi = 1e-9 * (1.0 + std::abs(max_[i]));
    applied_[i] = u;
    offsets_[i] = offsets[i];
    if (asked < min_[i] - tol_lo || asked > max_[i] + tol_hi) {
      status_[i] = LoopStatus::windup;
    } else if (u <= min_[i] + tol_lo) {
      status_[i] = LoopStatus::clamped_low;
    } else if (u >= max_[i] - tol_hi) {
      status_[i] = LoopStatus::clamped_high;
    } else {
      status_[i] = LoopStatus::ok;
    }
  }
}

void ClosedLoop::step(std::span<const double> y, std::uint16_t switch_value,
                      std::span<const double> mv_offsets,
                      std::span<const double> sp_offsets) noexcept {
  switch (switch_value) {
    case 0:
      requested_ = LoopMode::off;
      break;
    case 1:
    case 2:
      requested_ = LoopMode::control;
      break;
    case 3:
      requested_ = LoopMode::suspended;
      break;
    default:
      break;  // not a switch value: the last request stands
  }
  if (requested_ == LoopMode::off) {  // manual: every MV held, the controller stands still
    mode_ = LoopMode::off;
    std::fill(status_.begin(), status_.end(), LoopStatus::manual);
    return;
  }
  if (requested_ == LoopMode::suspended) {
    mode_ = LoopMode::suspended;
    apply(zeros_);
    return;
  }
  std::copy(sp_offsets.begin(), sp_offsets.end(), setpoints_.begin());
  const control::StepReport report = controller_->step(y, setpoints_, mv_offsets, moves_);
  if (report.status != control::StepStatus::ok) ++irregular_steps_;
  apply(mv_offsets);
  const bool testing =
      std::any_of(mv_offsets.begin(), mv_offsets.end(), [](double o) { return o != 0.0; }) ||
      std::any_of(sp_offsets.begin(), sp_offsets.end(), [](double r) { return r != 0.0; });
  mode_ = testing ? LoopMode::test : LoopMode::control;
}

void ClosedLoop::clear_offsets() noexcept {
  std::fill(setpoints_.begin(), setpoints_.end(), 0.0);
  if (mode_ == LoopMode::off) return;  // manual: the MVs are the operator's, held
  apply(zeros_);
  if (mode_ == LoopMode::test) mode_ = LoopMode::control;
}

}  // namespace excite::sim::server
