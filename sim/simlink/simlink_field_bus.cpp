// SPDX-License-Identifier: MIT
#include "sim/simlink/simlink_field_bus.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

namespace excite::sim::simlink {

using hal::StatusCode;

SimLinkFieldBus::SimLinkFieldBus(std::unique_ptr<Plant> plant, double sample_time_min,
                                 SimLinkConfig config, hal::VirtualClock* clock)
    : plant_(std::move(plant)), config_(std::move(config)), clock_(clock) {
  if (!plant_) throw std::invalid_argument("simlink plant is null, expected a sim::Plant");
  inputs_ = static_cast<std::size_t>(plant_->inputs());
  outputs_ = static_cast<std::size_t>(plant_->outputs());
  values_ = outputs_;
  held_.assign(inputs_, 0.0);
  du_.assign(inputs_, 0.0);
  y_.assign(outputs_, 0.0);
  disturbance_ = std::vector<std::atomic<double>>(outputs_);
  if (config_.input_baseline.empty()) {
    const Eigen::VectorXd u0 = plant_->input_baseline();
    config_.input_baseline.assign(u0.data(), u0.data() + u0.size());
  }
  if (config_.output_baseline.empty()) {
    const Eigen::VectorXd y0 = plant_->output_baseline();
    config_.output_baseline.assign(y0.data(), y0.data() + y0.size());
  }
  if (config_.input_baseline.size() != inputs_) {
    throw std::invalid_argument("simlink input_baseline has " +
                                std::to_string(config_.input_baseline.size()) +
                                " values, expected " + std::to_string(inputs_) + " (one per " +
                                plant_->name() + " input, or none for the plant's own)");
  }
  if (config_.output_baseline.size() != outputs_) {
    throw std::invalid_argument("simlink output_baseline has " +
                                std::to_string(config_.output_baseline.size()) +
                                " values, expected " + std::to_string(outputs_) + " (one per " +
                                plant_->name() + " output, or none for the plant's own)");
  }
  plant_->reset(sample_time_min);
  held_ = config_.input_baseline;
  for (auto& d : disturbance_) d.store(0.0);
  if (config_.readbacks) {
    readback_base_ = static_cast<int>(values_);
    values_ += inputs_;
  }
  if (config_.heartbeat_echo) echo_index_ = static_cast<int>(values_++);
  if (config_.command_register) command_index_ = static_cast<int>(values_++);
}

SimLinkFieldBus::SimLinkFieldBus(const TransferMatrix& g, double sample_time_min,
                                 SimLinkConfig config, hal::VirtualClock* clock)
    : SimLinkFieldBus(make_linear_plant("simlink", g), sample_time_min, std::move(config), clock) {}

int SimLinkFieldBus::readback_index(std::size_t input) const noexcept {
  if (readback_base_ < 0 || input >= inputs_) return -1;
  return readback_base_ + static_cast<int>(input);
}

void SimLinkFieldBus::drop(int calls, StatusCode status) noexcept {
  drop_status_.store(status);
  drop_calls_.store(calls);
}

void SimLinkFieldBus::set_disturbance(std::size_t output, double value) noexcept {
  if (output < outputs_) disturbance_[output].store(value);
}

bool SimLinkFieldBus::consume_drop(StatusCode& status) noexcept {
  int left = drop_calls_.load();
  while (left > 0 && !drop_calls_.compare_exchange_weak(left, left - 1)) {
  }
  if (left <= 0) return false;
  status = drop_status_.load();
  dropped_.fetch_add(1);
  detail_ = "simlink: exchange dropped on purpose";
  return true;
}

void SimLinkFieldBus::spend_time() noexcept {
  if (clock_ != nullptr) clock_->advance(config_.exchange_time);
}

StatusCode SimLinkFieldBus::write(std::span<const double> setpoints,
                                  std::uint16_t heartbeat) noexcept {
  spend_time();
  if (setpoints.size() != inputs_) {
    detail_ = "simlink: wrong number of setpoints";
    return StatusCode::bad_argument;
  }
  for (double s : setpoints) {
    if (!std::isfinite(s)) {
      detail_ = "simlink: non-finite setpoint";
      return StatusCode::bad_argument;
    }
  }
  StatusCode dropped = StatusCode::ok;
  const bool drop_this = consume_drop(dropped);
  if (!drop_this) {
    for (std::size_t i = 0; i < inputs_; ++i) held_[i] = setpoints[i];
    heartbeat_.store(heartbeat);
    if (!echo_frozen_.load()) echo_.store(heartbeat);
    writes_.fetch_add(1);
  }
  // The plant's time goes on whether or not the write arrived: one sample per write.
  for (std::size_t i = 0; i < inputs_; ++i) du_[i] = held_[i] - config_.input_baseline[i];
  try {
    plant_->step(du_, y_);
  } catch (const std::exception& e) {  // the plant refused the sample; it did not happen
    std::strncpy(plant_error_, e.what(), sizeof plant_error_ - 1);
    plant_error_[sizeof plant_error_ - 1] = '\0';
    detail_ = plant_error_;
    plant_errors_.fetch_add(1);
    return StatusCode::peer_error;
  }
  samples_.fetch_add(1);
  if (drop_this) return dropped;
  detail_ = "";
  return StatusCode::ok;
}

StatusCode SimLinkFieldBus::read(std::span<double> values) noexcept {
  spend_time();
  if (values.size() != values_) {
    detail_ = "simlink: wrong number of values";
    return StatusCode::bad_argument;
  }
  StatusCode dropped = StatusCode::ok;
  if (consume_drop(dropped)) return dropped;
  for (std::size_t j = 0; j < outputs_; ++j) {
    values[j] = config_.output_baseline[j] + y_[j] + disturbance_[j].load();
  }
  if (readback_base_ >= 0) {
    for (std::size_t i = 0; i < inputs_; ++i) {
      values[static_cast<std::size_t>(readback_base_) + i] = held_[i];
    }
  }
  if (echo_index_ >= 0) values[static_cast<std::size_t>(echo_index_)] = echo_.load();
  if (command_index_ >= 0) values[static_cast<std::size_t>(command_index_)] = command_.load();
  reads_.fetch_add(1);
  detail_ = "";
  return StatusCode::ok;
}

StatusCode SimLinkFieldBus::write_value(std::size_t index, double value) noexcept {
  spend_time();
  if (!value_writable(index) || !std::isfinite(value)) {
    detail_ = "simlink: write_value: only the command register, with a finite value";
    return StatusCode::unavailable;
  }
  command_.store(value);
  detail_ = "";
  return StatusCode::ok;
}

}  // namespace excite::sim::simlink
