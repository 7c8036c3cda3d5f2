// SPDX-License-Identifier: MIT
#include "sim/server/register_image.hpp"

#include <modbus.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "hal/modbus/word_order.hpp"

namespace excite::sim::server {

using hal::modbus::RegisterType;

RegisterImage::RegisterImage(ServerLayout layout, const std::vector<double>& input_baseline,
                             const std::vector<double>& output_baseline)
    : layout_(std::move(layout)),
      input_baseline_(input_baseline),
      last_setpoints_(input_baseline),
      written_(layout_.setpoints.size(), false),
      misfits_(layout_.values.size()) {
  if (input_baseline.size() != layout_.setpoints.size() ||
      output_baseline.size() != layout_.values.size()) {
    throw std::invalid_argument("RegisterImage: baselines do not match the layout");
  }
  mapping_ =
      modbus_mapping_new_start_address(0, 0, 0, 0, layout_.holding.start, layout_.holding.count,
                                       layout_.input.start, layout_.input.count);
  if (mapping_ == nullptr) {
    throw std::runtime_error(std::string("modbus_mapping_new_start_address: ") +
                             modbus_strerror(errno));
  }
  restore_setpoint_baseline();
  if (layout_.closed_loop) {  // at rest: offsets zero, the controller in control
    const ClosedLoopLayout& loop = *layout_.closed_loop;
    last_offsets_.assign(loop.mv_offsets.size() + loop.sp_offsets.size(), 0.0);
    restore_guarded();
    *cell(loop.controller_switch) = 1;
    *cell(loop.mode) = 1;
  }
  write_values(output_baseline.data());
  clamped_values_ = 0;  // a baseline outside the range is counted from the first sample on
  misfits_.assign(layout_.values.size(), Misfit{});
}

RegisterImage::~RegisterImage() {
  modbus_mapping_free(mapping_);
}

std::uint16_t* RegisterImage::cell(const PlacedValue& value) const {
  if (value.input_table) {
    return mapping_->tab_input_registers + (value.address - layout_.input.start);
  }
  return mapping_->tab_registers + (value.address - layout_.holding.start);
}

void RegisterImage::restore_setpoint_baseline() {
  for (std::size_t i = 0; i < layout_.setpoints.size(); ++i) {
    const PlacedValue& p = layout_.setpoints[i];
    std::uint16_t* r = cell(p);
    if (p.codec.type == RegisterType::float32) {
      hal::modbus::encode_float32(static_cast<float>(input_baseline_[i]), p.codec.order, r);
    } else {
      bool clamped = false;
      r[0] = hal::modbus::to_raw(p.codec, input_baseline_[i], clamped);
    }
  }
  last_setpoints_ = input_baseline_;
}

void RegisterImage::encode(const PlacedValue& p, double x) {
  std::uint16_t* r = cell(p);
  if (p.codec.type == RegisterType::float32) {
    hal::modbus::encode_float32(static_cast<float>(x), p.codec.order, r);
  } else {
    bool clamped = false;
    r[0] = hal::modbus::to_raw(p.codec, x, clamped);
  }
}

double RegisterImage::decode(const PlacedValue& p) const {
  const std::uint16_t* r = cell(p);
  return p.codec.type == RegisterType::float32
             ? static_cast<double>(hal::modbus::decode_float32(r, p.codec.order))
             : hal::modbus::from_raw(p.codec, r[0]);
}

std::vector<std::uint16_t> RegisterImage::guarded_registers() const {
  if (!layout_.closed_loop) return setpoint_registers();
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  const std::uint16_t* first =
      mapping_->tab_registers + (loop.offset_start - layout_.holding.start);
  return {first, first + loop.offset_count};
}

void RegisterImage::set_guarded_registers(const std::vector<std::uint16_t>& registers) {
  if (!layout_.closed_loop) {
    set_setpoint_registers(registers);
    return;
  }
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  std::uint16_t* first = mapping_->tab_registers + (loop.offset_start - layout_.holding.start);
  std::copy_n(registers.begin(), std::min<std::size_t>(registers.size(), loop.offset_count), first);
}

void RegisterImage::restore_guarded() {
  if (!layout_.closed_loop) {
    restore_setpoint_baseline();
    return;
  }
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  for (const PlacedValue& p : loop.mv_offsets) encode(p, 0.0);
  for (const PlacedValue& p : loop.sp_offsets) encode(p, 0.0);
  std::fill(last_offsets_.begin(), last_offsets_.end(), 0.0);
}

bool RegisterImage::touches_setpoints(std::uint32_t address, std::uint32_t count) const {
  for (const PlacedValue& p : layout_.setpoints) {
    const std::uint32_t size = hal::modbus::register_count(p.codec.type);
    if (p.address < address + count && address < p.address + size) return true;
  }
  return false;
}

void RegisterImage::read_offsets(double* mv_offsets, double* sp_offsets) {
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  const std::size_t n = loop.mv_offsets.size();
  for (std::size_t k = 0; k < last_offsets_.size(); ++k) {
    const double value = decode(k < n ? loop.mv_offsets[k] : loop.sp_offsets[k - n]);
    if (std::isfinite(value)) {
      last_offsets_[k] = value;
    } else {
      ++rejected_setpoints_;
    }
    (k < n ? mv_offsets[k] : sp_offsets[k - n]) = last_offsets_[k];
  }
}

std::uint16_t RegisterImage::controller_switch() const {
  return *cell(layout_.closed_loop->controller_switch);
}

void RegisterImage::write_controller(const double* moves, const double* applied,
                                     const double* setpoints, const std::uint16_t* status,
                                     std::uint16_t mode, const double* u) {
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  for (std::size_t i = 0; i < loop.moves.size(); ++i) {
    encode(loop.moves[i], moves[i]);
    encode(loop.applied[i], applied[i]);
    *cell(loop.status[i]) = status[i];
    encode(layout_.setpoints[i], u[i]);
  }
  for (std::size_t j = 0; j < loop.setpoints.size(); ++j) encode(loop.setpoints[j], setpoints[j]);
  *cell(loop.mode) = mode;
}

std::vector<std::uint16_t> RegisterImage::setpoint_registers() const {
  std::vector<std::uint16_t> out;
  for (const PlacedValue& p : layout_.setpoints) {
    const std::uint16_t* r = cell(p);
    out.insert(out.end(), r, r + hal::modbus::register_count(p.codec.type));
  }
  return out;
}

void RegisterImage::set_setpoint_registers(const std::vector<std::uint16_t>& registers) {
  std::size_t at = 0;
  for (const PlacedValue& p : layout_.setpoints) {
    std::uint16_t* r = cell(p);
    for (std::uint32_t k = 0;
         k < hal::modbus::register_count(p.codec.type) && at < registers.size(); ++k) {
      r[k] = registers[at++];
    }
  }
}

std::optional<double> RegisterImage::value_after_write(const PlacedValue& p, std::uint32_t address,
                                                       std::uint32_t count,
                                                       const std::uint8_t* data) const {
  const std::uint32_t size = hal::modbus::register_count(p.codec.type);
  if (!(p.address < address + count && address < p.address + size)) return std::nullopt;
  std::uint16_t r[2] = {0, 0};
  const std::uint16_t* old = cell(p);
  for (std::uint32_t k = 0; k < size; ++k) {
    const std::uint32_t a = p.address + k;
    r[k] = address <= a && a < address + count
               ? static_cast<std::uint16_t>((data[2 * (a - address)] << 8) |
                                            data[2 * (a - address) + 1])
               : old[k];
  }
  return p.codec.type == RegisterType::float32
             ? static_cast<double>(hal::modbus::decode_float32(r, p.codec.order))
             : hal::modbus::from_raw(p.codec, r[0]);
}

std::optional<RegisterImage::OutOfLimits> RegisterImage::check_offset_write(
    std::uint32_t address, std::uint32_t count, const std::uint8_t* data,
    const std::vector<double>& limit) const {
  if (!layout_.closed_loop) return std::nullopt;
  const ClosedLoopLayout& loop = *layout_.closed_loop;
  const std::size_t n = loop.mv_offsets.size();
  for (std::size_t k = 0; k < n + loop.sp_offsets.size() && k < limit.size(); ++k) {
    const PlacedValue& p = k < n ? loop.mv_offsets[k] : loop.sp_offsets[k - n];
    const auto value = value_after_write(p, address, count, data);
    if (!value) continue;
    // float32 offsets: the bound is allowed its register's rounding (relative 2^-23).
    const double bound = limit[k] * (1.0 + 0x1p-23);
    if (!std::isfinite(*value) || std::abs(*value) > bound) return OutOfLimits{k, *value};
  }
  return std::nullopt;
}

std::optional<RegisterImage::OutOfLimits> RegisterImage::check_write(
    std::uint32_t address, std::uint32_t count, const std::uint8_t* data,
    const std::vector<double>& min, const std::vector<double>& max) const {
  for (std::size_t i = 0; i < layout_.setpoints.size() && i < min.size() && i < max.size(); ++i) {
    const PlacedValue& p = layout_.setpoints[i];
    const auto written = value_after_write(p, address, count, data);
    if (!written) continue;
    const double value = *written;
    const bool f32 = p.codec.type == RegisterType::float32;
    const double tolerance = f32 ? (std::abs(min[i]) + std::abs(max[i])) * 0x1p-23 : 0.0;
    if (!std::isfinite(value) || value < min[i] - tolerance || value > max[i] + tolerance) {
      return OutOfLimits{i, value};
    }
  }
  return std::nullopt;
}

void RegisterImage::note_write(std::uint32_t address, std::uint32_t count) {
  for (std::size_t i = 0; i < layout_.setpoints.size(); ++i) {
    const PlacedValue& p = layout_.setpoints[i];
    const std::uint32_t size = hal::modbus::register_count(p.codec.type);
    if (p.address < address + count && address < p.address + size) {
      written_[i] = true;
    }
  }
}

void RegisterImage::read_setpoints(double* u) {
  for (std::size_t i = 0; i < layout_.setpoints.size(); ++i) {
    const PlacedValue& p = layout_.setpoints[i];
    if (!written_[i]) {
      u[i] = last_setpoints_[i];
      continue;
    }
    const std::uint16_t* r = cell(p);
    const double value = p.codec.type == RegisterType::float32
                             ? static_cast<double>(hal::modbus::decode_float32(r, p.codec.order))
                             : hal::modbus::from_raw(p.codec, r[0]);
    if (std::isfinite(value)) {
      last_setpoints_[i] = value;
    } else {
      ++rejected_setpoints_;
    }
    u[i] = last_setpoints_[i];
  }
}

void RegisterImage::write_values(const double* y) {
  for (std::size_t j = 0; j < layout_.values.size(); ++j) {
    const PlacedValue& p = layout_.values[j];
    std::uint16_t* r = cell(p);
    if (p.codec.type == RegisterType::float32) {
      hal::modbus::encode_float32(static_cast<float>(y[j]), p.codec.order, r);
    } else {
      bool clamped = false;
      r[0] = hal::modbus::to_raw(p.codec, y[j], clamped);
      if (clamped) {
        ++clamped_values_;
        Misfit& m = misfits_[j];
        m.lowest = m.count == 0 ? y[j] : std::min(m.lowest, y[j]);
        m.highest = m.count == 0 ? y[j] : std::max(m.highest, y[j]);
        ++m.count;
      }
    }
  }
}

std::uint16_t RegisterImage::heartbeat() const {
  return holding(layout_.heartbeat_address);
}

std::uint16_t RegisterImage::heartbeat_echo() const {
  return *cell(layout_.heartbeat_echo);
}

void RegisterImage::set_heartbeat_echo(std::uint16_t value) {
  *cell(layout_.heartbeat_echo) = value;
}

std::uint16_t RegisterImage::control(std::uint32_t index) const {
  return holding(*layout_.control_address + index);
}

void RegisterImage::set_control(std::uint32_t index, std::uint16_t value) {
  set_holding(*layout_.control_address + index, value);
}

bool RegisterImage::in_holding(std::uint32_t address) const {
  return address >= layout_.holding.start &&
         address < layout_.holding.start + layout_.holding.count;
}

std::uint16_t RegisterImage::holding(std::uint32_t address) const {
  return mapping_->tab_registers[address - layout_.holding.start];
}

void RegisterImage::set_holding(std::uint32_t address, std::uint16_t value) {
  mapping_->tab_registers[address - layout_.holding.start] = value;
}

std::uint16_t RegisterImage::input(std::uint32_t address) const {
  return mapping_->tab_input_registers[address - layout_.input.start];
}

}  // namespace excite::sim::server
