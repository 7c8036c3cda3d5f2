// SPDX-License-Identifier: MIT
#include "hal/modbus/register_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "base/config/document.hpp"

namespace excite::hal::modbus {

namespace {

// One register block to place: a value or the heartbeat.
struct Item {
  std::string field;  // the address field: "setpoints[3].address" or "heartbeat_address"
  std::uint32_t address = 0;
  std::uint32_t size = 0;
  int function_code = 16;
  Codec* codec = nullptr;  // null for the heartbeat
  bool heartbeat = false;
};

std::optional<RegisterType> parse_type(const std::string& text) {
  if (text == "float32") return RegisterType::float32;
  if (text == "int16") return RegisterType::int16;
  if (text == "uint16") return RegisterType::uint16;
  return std::nullopt;
}

config::Check compile_entry(const RegisterEntry& entry, const std::string& field, bool is_setpoint,
                            Codec& codec, Item& item) {
  if (is_setpoint && entry.function_code != 16) {
    return config::Check::invalid(field + ".function_code", std::to_string(entry.function_code),
                                  "16 (write multiple registers) for a setpoint");
  }
  if (!is_setpoint && entry.function_code != 3 && entry.function_code != 4) {
    return config::Check::invalid(field + ".function_code", std::to_string(entry.function_code),
                                  "3 (holding registers) or 4 (input registers) for a value");
  }
  const auto type = parse_type(entry.type);
  if (!type) {
    return config::Check::invalid(field + ".type", "\"" + entry.type + "\"",
                                  "float32, int16 or uint16");
  }
  codec.type = *type;
  const std::uint32_t size = register_count(*type);
  if (entry.address >= address_space || entry.address + size > address_space) {
    return config::Check::invalid(field + ".address", std::to_string(entry.address),
                                  "address + " + std::to_string(size) + " register(s) <= 65536");
  }
  if (*type == RegisterType::float32) {
    const auto order = parse_word_order(entry.word_order);
    if (!order) {
      return config::Check::invalid(field + ".word_order", "\"" + entry.word_order + "\"",
                                    "ABCD, CDAB, BADC or DCBA");
    }
    codec.order = *order;
  } else {
    if (!std::isfinite(entry.eng_min) || !std::isfinite(entry.eng_max) ||
        !(entry.eng_min < entry.eng_max)) {
      return config::Check::invalid(field + ".eng_max", config::format_number(entry.eng_max),
                                    "a finite engineering range with eng_min (" +
                                        config::format_number(entry.eng_min) + ") < eng_max");
    }
    const std::int32_t type_min = *type == RegisterType::int16 ? -32768 : 0;
    const std::int32_t type_max = *type == RegisterType::int16 ? 32767 : 65535;
    const std::int32_t raw_min = entry.raw_min.value_or(type_min);
    const std::int32_t raw_max = entry.raw_max.value_or(type_max);
    const std::string span = std::to_string(type_min) + ".." + std::to_string(type_max);
    if (raw_min < type_min || raw_min > type_max) {
      return config::Check::invalid(field + ".raw_min", std::to_string(raw_min),
                                    "within " + span + " for " + entry.type);
    }
    if (raw_max < type_min || raw_max > type_max || raw_max <= raw_min) {
      return config::Check::invalid(
          field + ".raw_max", std::to_string(raw_max),
          "within " + span + " and > raw_min (" + std::to_string(raw_min) + ")");
    }
    codec.eng_min = entry.eng_min;
    codec.eng_max = entry.eng_max;
    codec.raw_min = raw_min;
    codec.raw_max = raw_max;
  }
  codec.address = static_cast<std::uint16_t>(entry.address);
  codec.function_code = entry.function_code;
  item = Item{field + ".address", entry.address, size, entry.function_code, &codec, false};
  return config::Check::valid();
}

// Sorts the items of one register table, rejects overlaps, and splits contiguous runs
// into requests of at most `chunk` registers without splitting a value.
config::Check plan_requests(std::vector<Item>& items, std::uint32_t chunk,
                            std::vector<Request>& requests, std::size_t& image_size,
                            std::optional<std::size_t>& heartbeat_offset) {
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.function_code != b.function_code ? a.function_code < b.function_code
                                              : a.address < b.address;
  });
  std::size_t offset = 0;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& item = items[i];
    if (i > 0) {
      const Item& previous = items[i - 1];
      if (previous.function_code == item.function_code &&
          previous.address + previous.size > item.address) {
        return config::Check::invalid(item.field, std::to_string(item.address),
                                      "no overlap with " + previous.field + " (registers " +
                                          std::to_string(previous.address) + ".." +
                                          std::to_string(previous.address + previous.size - 1) +
                                          ")");
      }
    }
    const bool extends = !requests.empty() && requests.back().function_code == item.function_code &&
                         requests.back().address + requests.back().count == item.address &&
                         requests.back().count + item.size <= chunk;
    if (extends) {
      requests.back().count = static_cast<std::uint16_t>(requests.back().count + item.size);
    } else {
      requests.push_back(Request{item.function_code, static_cast<std::uint16_t>(item.address),
                                 static_cast<std::uint16_t>(item.size), offset});
    }
    if (item.heartbeat) {
      heartbeat_offset = offset;
    } else {
      item.codec->offset = offset;
    }
    offset += item.size;
  }
  image_size = offset;
  return config::Check::valid();
}

}  // namespace

std::uint32_t register_count(RegisterType type) noexcept {
  return type == RegisterType::float32 ? 2U : 1U;
}

config::Check compile_register_map(const RegisterMap& map, RegisterPlan& plan) {
  plan = RegisterPlan{};
  if (map.write_chunk < 2 || map.write_chunk > max_write_registers) {
    return config::Check::invalid("write_chunk", std::to_string(map.write_chunk),
                                  "2..123 registers per FC16 request (protocol limit 123)");
  }
  if (map.read_chunk < 2 || map.read_chunk > max_read_registers) {
    return config::Check::invalid("read_chunk", std::to_string(map.read_chunk),
                                  "2..125 registers per FC03/FC04 request (protocol limit 125)");
  }
  RegisterPlan compiled;
  compiled.setpoints.resize(map.setpoints.size());
  compiled.values.resize(map.values.size());

  std::vector<Item> writes(map.setpoints.size());
  for (std::size_t i = 0; i < map.setpoints.size(); ++i) {
    const std::string field = "setpoints[" + std::to_string(i) + "]";
    if (auto v = compile_entry(map.setpoints[i], field, true, compiled.setpoints[i], writes[i]);
        !v.ok()) {
      return v;
    }
  }
  if (map.heartbeat_address) {
    if (*map.heartbeat_address >= address_space) {
      return config::Check::invalid("heartbeat_address", std::to_string(*map.heartbeat_address),
                                    "address + 1 register <= 65536");
    }
    writes.push_back(Item{"heartbeat_address", *map.heartbeat_address, 1, 16, nullptr, true});
  }
  std::vector<Item> reads(map.values.size());
  for (std::size_t i = 0; i < map.values.size(); ++i) {
    const std::string field = "values[" + std::to_string(i) + "]";
    if (auto v = compile_entry(map.values[i], field, false, compiled.values[i], reads[i]);
        !v.ok()) {
      return v;
    }
  }
  if (auto v = plan_requests(writes, map.write_chunk, compiled.writes, compiled.write_image_size,
                             compiled.heartbeat_offset);
      !v.ok()) {
    return v;
  }
  std::optional<std::size_t> no_heartbeat;
  if (auto v = plan_requests(reads, map.read_chunk, compiled.reads, compiled.read_image_size,
                             no_heartbeat);
      !v.ok()) {
    return v;
  }
  plan = std::move(compiled);
  return config::Check::valid();
}

std::uint16_t to_raw(const Codec& codec, double engineering, bool& clamped) noexcept {
  clamped = engineering < codec.eng_min || engineering > codec.eng_max;
  const double eng = std::clamp(engineering, codec.eng_min, codec.eng_max);
  const double raw = codec.raw_min + (eng - codec.eng_min) * (codec.raw_max - codec.raw_min) /
                                         (codec.eng_max - codec.eng_min);
  const auto rounded =
      static_cast<std::int32_t>(std::lround(std::clamp(raw, codec.raw_min, codec.raw_max)));
  // int16 travels as its two's-complement bit pattern.
  return static_cast<std::uint16_t>(rounded & 0xFFFF);
}

double from_raw(const Codec& codec, std::uint16_t raw) noexcept {
  const double value = codec.type == RegisterType::int16
                           ? static_cast<double>(static_cast<std::int16_t>(raw))
                           : static_cast<double>(raw);
  return codec.eng_min + (value - codec.raw_min) * (codec.eng_max - codec.eng_min) /
                             (codec.raw_max - codec.raw_min);
}

}  // namespace excite::hal::modbus
