// SPDX-License-Identifier: MIT
#include "hal/can/frame_map.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace excite::hal::can {

namespace {

struct TypeInfo {
  const char* name;
  SignalType type;
  std::uint8_t size;
  double min;
  double max;
};

constexpr TypeInfo types[] = {
    {"int8", SignalType::int8, 1, -128.0, 127.0},
    {"uint8", SignalType::uint8, 1, 0.0, 255.0},
    {"int16", SignalType::int16, 2, -32768.0, 32767.0},
    {"uint16", SignalType::uint16, 2, 0.0, 65535.0},
    {"int32", SignalType::int32, 4, -2147483648.0, 2147483647.0},
    {"uint32", SignalType::uint32, 4, 0.0, 4294967295.0},
    {"float32", SignalType::float32, 4, -static_cast<double>(std::numeric_limits<float>::max()),
     static_cast<double>(std::numeric_limits<float>::max())},
};

const TypeInfo& info(SignalType type) noexcept {
  return types[static_cast<std::size_t>(type)];
}

}  // namespace

bool raw_range(SignalType type, double& low, double& high) noexcept {
  if (type == SignalType::float32) return false;
  low = info(type).min;
  high = info(type).max;
  return true;
}

namespace {

std::string hex(std::uint32_t x) {
  static constexpr char digits[] = "0123456789ABCDEF";
  std::string text;
  do {
    text.insert(text.begin(), digits[x & 0xFU]);
    x >>= 4U;
  } while (x != 0);
  return "0x" + text;
}

canid_t frame_id(const CanSignal& signal) {
  return signal.extended ? (signal.id | CAN_EFF_FLAG) : signal.id;
}

// The frames of one direction: identifiers in first-seen order, with a byte-use mask each.
struct FrameSlots {
  std::vector<canid_t> ids;
  std::vector<std::uint8_t> used;  // bit b: byte b taken
  std::vector<std::string> owner;  // who took each byte, for messages: per frame, 8 names
  std::vector<std::uint8_t> dlc;
};

config::Check place(const CanSignal& signal, const std::string& field, FrameSlots& slots,
                    SignalCodec& codec) {
  const std::uint32_t id_limit = signal.extended ? CAN_EFF_MASK : CAN_SFF_MASK;
  if (signal.id > id_limit) {
    return config::Check::invalid(field + ".id", hex(signal.id),
                                  signal.extended
                                      ? "0x0..0x1FFFFFFF (29-bit extended identifier)"
                                      : "0x0..0x7FF (11-bit identifier; set extended for 29-bit)");
  }
  const TypeInfo* type = nullptr;
  for (const TypeInfo& candidate : types) {
    if (signal.type == candidate.name) {
      type = &candidate;
    }
  }
  if (type == nullptr) {
    return config::Check::invalid(field + ".type", "\"" + signal.type + "\"",
                                  "int8, uint8, int16, uint16, int32, uint32 or float32");
  }
  if (signal.byte_order != "little" && signal.byte_order != "big") {
    return config::Check::invalid(field + ".byte_order", "\"" + signal.byte_order + "\"",
                                  "\"little\" or \"big\"");
  }
  if (signal.byte_offset > 7 || signal.byte_offset + type->size > 8) {
    return config::Check::invalid(field + ".byte_offset", std::to_string(signal.byte_offset),
                                  "byte_offset + " + std::to_string(type->size) + " byte(s) of " +
                                      signal.type + " <= 8 (classic CAN payload)");
  }
  if (!std::isfinite(signal.scale) || signal.scale == 0.0) {
    return config::Check::invalid(field + ".scale", std::to_string(signal.scale),
                                  "a finite, non-zero scale");
  }
  if (!std::isfinite(signal.offset)) {
    return config::Check::invalid(field + ".offset", std::to_string(signal.offset),
                                  "a finite offset");
  }
  const canid_t id = frame_id(signal);
  auto found = std::find(slots.ids.begin(), slots.ids.end(), id);
  const auto frame = static_cast<std::size_t>(found - slots.ids.begin());
  if (found == slots.ids.end()) {
    slots.ids.push_back(id);
    slots.used.push_back(0);
    slots.owner.resize(slots.owner.size() + 8);
    slots.dlc.push_back(0);
  }
  const auto mask = static_cast<std::uint8_t>(((1U << type->size) - 1U) << signal.byte_offset);
  if ((slots.used[frame] & mask) != 0) {
    std::string other;
    for (std::uint32_t b = signal.byte_offset; b < signal.byte_offset + type->size; ++b) {
      if (!slots.owner[frame * 8 + b].empty()) {
        other = slots.owner[frame * 8 + b];
        break;
      }
    }
    return config::Check::invalid(field + ".byte_offset", std::to_string(signal.byte_offset),
                                  "no overlap with " + other + " in frame " + hex(signal.id));
  }
  slots.used[frame] = static_cast<std::uint8_t>(slots.used[frame] | mask);
  for (std::uint32_t b = signal.byte_offset; b < signal.byte_offset + type->size; ++b) {
    slots.owner[frame * 8 + b] = field;
  }
  slots.dlc[frame] =
      std::max(slots.dlc[frame], static_cast<std::uint8_t>(signal.byte_offset + type->size));
  codec = SignalCodec{frame,
                      static_cast<std::uint8_t>(signal.byte_offset),
                      type->size,
                      type->type,
                      signal.byte_order == "big",
                      signal.scale,
                      signal.offset};
  return config::Check::valid();
}

void store(std::uint8_t* data, const SignalCodec& codec, std::uint32_t bits) noexcept {
  for (std::uint8_t i = 0; i < codec.size; ++i) {
    const std::uint8_t shift =
        static_cast<std::uint8_t>(8U * (codec.big_endian ? codec.size - 1U - i : i));
    data[codec.offset + i] = static_cast<std::uint8_t>(bits >> shift);
  }
}

std::uint32_t load(const std::uint8_t* data, const SignalCodec& codec) noexcept {
  std::uint32_t bits = 0;
  for (std::uint8_t i = 0; i < codec.size; ++i) {
    const std::uint8_t shift =
        static_cast<std::uint8_t>(8U * (codec.big_endian ? codec.size - 1U - i : i));
    bits |= static_cast<std::uint32_t>(data[codec.offset + i]) << shift;
  }
  return bits;
}

// Raw integer bit pattern of a (clamped, rounded) raw value.
std::uint32_t to_bits(const SignalCodec& codec, double raw, bool& clamped) noexcept {
  const TypeInfo& type = info(codec.type);
  if (codec.type == SignalType::float32) {
    clamped = raw < type.min || raw > type.max;
    return std::bit_cast<std::uint32_t>(static_cast<float>(std::clamp(raw, type.min, type.max)));
  }
  const double rounded = std::nearbyint(raw);
  clamped = rounded < type.min || rounded > type.max;
  const auto integer = static_cast<std::int64_t>(std::clamp(rounded, type.min, type.max));
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(integer) & 0xFFFFFFFFU);
}

double from_bits(const SignalCodec& codec, std::uint32_t bits) noexcept {
  switch (codec.type) {
    case SignalType::int8:
      return static_cast<std::int8_t>(bits);
    case SignalType::uint8:
      return static_cast<double>(bits);
    case SignalType::int16:
      return static_cast<std::int16_t>(bits);
    case SignalType::uint16:
      return static_cast<double>(bits);
    case SignalType::int32:
      return static_cast<std::int32_t>(bits);
    case SignalType::uint32:
      return static_cast<double>(bits);
    case SignalType::float32:
      return static_cast<double>(std::bit_cast<float>(bits));
  }
  return 0.0;
}

}  // namespace

config::Check compile_frame_map(const CanFrameMap& map, CanPlan& plan) {
  plan = CanPlan{};
  CanPlan compiled;
  FrameSlots tx;
  FrameSlots rx;
  compiled.setpoints.resize(map.setpoints.size());
  compiled.values.resize(map.values.size());
  for (std::size_t i = 0; i < map.setpoints.size(); ++i) {
    if (auto v = place(map.setpoints[i], "setpoints[" + std::to_string(i) + "]", tx,
                       compiled.setpoints[i]);
        !v.ok()) {
      return v;
    }
  }
  if (map.heartbeat) {
    if (map.heartbeat->type != "uint8" && map.heartbeat->type != "uint16") {
      return config::Check::invalid("heartbeat.type", "\"" + map.heartbeat->type + "\"",
                                    "uint8 or uint16 (a counter)");
    }
    SignalCodec codec;
    if (auto v = place(*map.heartbeat, "heartbeat", tx, codec); !v.ok()) {
      return v;
    }
    compiled.heartbeat = codec;
  }
  for (std::size_t i = 0; i < map.values.size(); ++i) {
    const std::string field = "values[" + std::to_string(i) + "]";
    if (std::find(tx.ids.begin(), tx.ids.end(), frame_id(map.values[i])) != tx.ids.end()) {
      return config::Check::invalid(
          field + ".id", hex(map.values[i].id),
          "an identifier not also used for setpoints (a frame is sent or received)");
    }
    if (auto v = place(map.values[i], field, rx, compiled.values[i]); !v.ok()) {
      return v;
    }
  }
  for (std::size_t f = 0; f < tx.ids.size(); ++f) {
    can_frame frame{};
    frame.can_id = tx.ids[f];
    frame.can_dlc = tx.dlc[f];
    compiled.tx.push_back(frame);
  }
  for (std::size_t f = 0; f < rx.ids.size(); ++f) {
    compiled.rx.push_back(RxFrame{rx.ids[f], rx.dlc[f]});
  }
  plan = std::move(compiled);
  return config::Check::valid();
}

StatusCode pack_setpoints(const CanPlan& plan, std::span<const double> setpoints,
                          std::uint16_t heartbeat, std::span<can_frame> frames,
                          std::uint64_t& clamped) noexcept {
  if (setpoints.size() != plan.setpoints.size() || frames.size() != plan.tx.size()) {
    return StatusCode::bad_argument;
  }
  for (double setpoint : setpoints) {
    if (!std::isfinite(setpoint)) {
      return StatusCode::bad_argument;
    }
  }
  for (std::size_t f = 0; f < frames.size(); ++f) {
    frames[f] = plan.tx[f];  // id, dlc; data zeroed
  }
  for (std::size_t i = 0; i < setpoints.size(); ++i) {
    const SignalCodec& codec = plan.setpoints[i];
    bool was_clamped = false;
    const std::uint32_t bits =
        to_bits(codec, (setpoints[i] - codec.offset_eng) / codec.scale, was_clamped);
    clamped += was_clamped ? 1U : 0U;
    store(frames[codec.frame].data, codec, bits);
  }
  if (plan.heartbeat) {
    const std::uint32_t counter = plan.heartbeat->size == 1 ? heartbeat & 0xFFU : heartbeat;
    store(frames[plan.heartbeat->frame].data, *plan.heartbeat, counter);
  }
  return StatusCode::ok;
}

std::optional<std::size_t> find_rx(const CanPlan& plan, const can_frame& frame) noexcept {
  if ((frame.can_id & (CAN_ERR_FLAG | CAN_RTR_FLAG)) != 0) {
    return std::nullopt;
  }
  for (std::size_t f = 0; f < plan.rx.size(); ++f) {
    if (plan.rx[f].id == frame.can_id) {
      return f;
    }
  }
  return std::nullopt;
}

bool unpack_values(const CanPlan& plan, std::size_t rx_index, const can_frame& frame,
                   std::span<double> values) noexcept {
  if (rx_index >= plan.rx.size() || frame.can_dlc < plan.rx[rx_index].dlc ||
      values.size() != plan.values.size()) {
    return false;
  }
  for (std::size_t i = 0; i < plan.values.size(); ++i) {
    const SignalCodec& codec = plan.values[i];
    if (codec.frame == rx_index) {
      values[i] = from_bits(codec, load(frame.data, codec)) * codec.scale + codec.offset_eng;
    }
  }
  return true;
}

}  // namespace excite::hal::can
