// SPDX-License-Identifier: MIT
#include "sim/lti/disturbance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace excite::sim {
namespace {

std::string text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

ColouredDisturbance::ColouredDisturbance(int outputs, double std_dev, double tau_min,
                                         double sample_time_min, std::uint64_t seed)
    : source_(seed) {
  if (outputs < 1) {
    throw std::invalid_argument("disturbance outputs = " + std::to_string(outputs) +
                                ", expected at least 1");
  }
  if (!std::isfinite(std_dev) || std_dev < 0.0) {
    throw std::invalid_argument("disturbance std = " + text(std_dev) +
                                ", expected a finite number >= 0");
  }
  if (!std::isfinite(tau_min) || tau_min <= 0.0) {
    throw std::invalid_argument("disturbance tau_min = " + text(tau_min) +
                                ", expected a finite number of minutes > 0");
  }
  if (!std::isfinite(sample_time_min) || sample_time_min <= 0.0) {
    throw std::invalid_argument("sample_time_min = " + text(sample_time_min) +
                                ", expected a finite number > 0");
  }
  state_.assign(static_cast<std::size_t>(outputs), 0.0);
  pole_ = std::exp(-sample_time_min / tau_min);
  drive_ = std_dev * std::sqrt(1.0 - pole_ * pole_);
}

void ColouredDisturbance::add(std::span<double> y) noexcept {
  const std::size_t n = std::min(y.size(), state_.size());
  for (std::size_t i = 0; i < n; ++i) {
    y[i] += state_[i];
    state_[i] = pole_ * state_[i] + drive_ * source_.next();
  }
}

}  // namespace excite::sim
