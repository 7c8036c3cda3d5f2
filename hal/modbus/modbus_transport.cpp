// SPDX-License-Identifier: MIT
#include "hal/modbus/modbus_transport.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "base/config/writer.hpp"
#include "hal/modbus/register_entry_toml.hpp"

namespace excite::hal::modbus {

namespace {

// The end-of-run line: "exception replies by code: 3 (illegal data value) 1, 4 (…) 2", or
// "… none".
std::string exception_counts_text(const ModbusFieldBus& bus) {
  std::string out;
  const std::span<const std::uint64_t> counts = bus.exception_counts();
  for (std::size_t code = 0; code < counts.size(); ++code) {
    if (counts[code] == 0) continue;
    out += (out.empty() ? "" : ", ") + std::to_string(code) + " (" +
           exception_name(static_cast<int>(code)) + ") " + std::to_string(counts[code]);
  }
  return "exception replies by code: " + (out.empty() ? std::string("none") : out);
}

std::string encoding(const RegisterEntry& e) {
  return e.type + (e.type == "float32" ? " " + e.word_order : std::string());
}

class ModbusTransport final : public TransportConfig {
 public:
  explicit ModbusTransport(std::string_view name) : name_(name) {
    config_.device.transport = name == "modbus-rtu" ? "rtu" : "tcp";
  }

  [[nodiscard]] std::string_view name() const noexcept override { return name_; }
  [[nodiscard]] const ModbusConfig& config() const noexcept { return config_; }

  [[nodiscard]] std::vector<std::string> device_keys() const override {
    return {"host",      "port",    "serial_port",        "baud", "parity", "data_bits",
            "stop_bits", "unit_id", "response_timeout_ms"};
  }

  void read_device(const config::Table& t) override {
    ModbusDevice& d = config_.device;
    if (auto s = t.text("host")) d.host = *s;
    if (auto v = t.integer("port", 0, 1 << 30)) d.port = static_cast<std::uint32_t>(*v);
    if (auto s = t.text("serial_port")) d.serial_port = *s;
    if (auto v = t.integer("baud", 0, 1 << 30)) d.baud = static_cast<std::int32_t>(*v);
    if (auto s = t.text("parity")) d.parity = *s;
    if (auto v = t.integer("data_bits", 0, 64)) d.data_bits = static_cast<std::int32_t>(*v);
    if (auto v = t.integer("stop_bits", 0, 64)) d.stop_bits = static_cast<std::int32_t>(*v);
    if (auto v = t.integer("unit_id", -1, 1 << 16)) d.unit_id = static_cast<std::int32_t>(*v);
    if (auto v = t.integer("response_timeout_ms", 1, 60000)) {
      d.response_timeout_ms = static_cast<std::int32_t>(*v);
    }
  }

  [[nodiscard]] std::vector<std::string> sections() const override { return {"map"}; }

  // [map]: the heartbeat register and the request sizes (optional).
  void read_sections(const config::Table& root) override {
    const toml::node* n = root.get("map");
    if (n == nullptr) return;
    if (!n->is_table()) throw config::Error("map", config::describe(*n), "a table [map]");
    const config::Table map(*n->as_table(), "map", root.source());
    map.only_keys({"heartbeat_address", "read_chunk", "write_chunk"});
    read_map_settings(map, config_.map);
  }

  [[nodiscard]] std::vector<std::string> entry_keys() const override {
    return {register_entry_keys.begin(), register_entry_keys.end()};
  }

  // hal's register-map schema, the same the plant server reads (defaults included).
  void read_entry(const config::Table& entry, ChannelKind kind, const std::string& name) override {
    RegisterEntry e = read_register_entry(
        entry, kind == ChannelKind::setpoint ? EntryKind::setpoint : EntryKind::value);
    e.name = name;
    (kind == ChannelKind::setpoint ? config_.map.setpoints : config_.map.values).push_back(e);
  }

  void validate() const override {
    const config::Check v = modbus::validate(config_);
    if (!v.ok()) throw config::Error(v);
  }

  // Runs after validate() (types and word orders are known good). A wrong word_order would
  // send the plant values up to 1e33 before any mismatch showed.
  void check_readback(std::size_t setpoint, std::size_t value) const override {
    if (setpoint >= config_.map.setpoints.size() || value >= config_.map.values.size()) return;
    const RegisterEntry& w = config_.map.setpoints[setpoint];
    const RegisterEntry& r = config_.map.values[value];
    const bool same_register = r.function_code == 3 && r.address == w.address;
    const bool same_encoding =
        r.type == w.type && (w.type != "float32" || r.word_order == w.word_order) &&
        (w.type == "float32" || (r.eng_min == w.eng_min && r.eng_max == w.eng_max &&
                                 r.raw_min == w.raw_min && r.raw_max == w.raw_max));
    if (same_register && !same_encoding) {
      throw config::Error("setpoints[" + std::to_string(setpoint) + "] (" + w.name + ") register " +
                              std::to_string(w.address),
                          encoding(w),
                          "the encoding its readback " + r.name +
                              " reads the same register with (" + encoding(r) + ")");
    }
  }

  [[nodiscard]] MadeBus make_bus(const Clock& /*clock*/,
                                 std::optional<std::size_t> /*await_echo*/) const override {
    // Each read is a request answered by the peer: no clock, no echo to wait for.
    MadeBus made;
    auto bus = std::make_unique<ModbusFieldBus>();
    if (const config::Check v = bus->configure(config_); !v.ok()) {
      made.error = v.message();
      return made;
    }
    const ModbusFieldBus* counted = bus.get();
    made.counts_report = [counted] { return exception_counts_text(*counted); };
    made.bus = std::move(bus);
    return made;
  }

  [[nodiscard]] std::string describe_peer() const override {
    const ModbusDevice& d = config_.device;
    if (d.transport == "tcp") {
      return "modbus-tcp " + d.host + ":" + std::to_string(d.port) + " unit " +
             std::to_string(d.unit_id) + ", response timeout " +
             std::to_string(d.response_timeout_ms) + " ms";
    }
    return "modbus-rtu " + d.serial_port + " " + std::to_string(d.baud) + " baud " + d.parity +
           std::to_string(d.data_bits) + std::to_string(d.stop_bits) + " unit " +
           std::to_string(d.unit_id) + ", response timeout " +
           std::to_string(d.response_timeout_ms) + " ms";
  }

  [[nodiscard]] std::string describe_channel(ChannelKind kind, std::size_t i) const override {
    const RegisterEntry& r = entry(kind, i);
    return "register " + std::to_string(r.address) + " " + encoding(r);
  }

  [[nodiscard]] std::string channel_columns(ChannelKind kind, std::size_t i) const override {
    const RegisterEntry& r = entry(kind, i);
    char text[96];
    if (kind == ChannelKind::setpoint) {
      std::snprintf(text, sizeof text, "register %5u %-7s %-4s", r.address, r.type.c_str(),
                    r.type == "float32" ? r.word_order.c_str() : "");
    } else {
      std::snprintf(text, sizeof text, "register %5u FC%02d %-7s", r.address, r.function_code,
                    r.type.c_str());
    }
    return text;
  }

  [[nodiscard]] std::string heartbeat_columns() const override {
    if (!config_.map.heartbeat_address) return "";
    char text[48];
    std::snprintf(text, sizeof text, "register %5u uint16", *config_.map.heartbeat_address);
    return text;
  }

  // hal clamps a setpoint to [eng_min, eng_max] (= raw_min..raw_max); a value is converted
  // from its raw reading without clamping, so the raw range's ends are the "end of the
  // register's range" (a server clamps there too). float32: unbounded.
  [[nodiscard]] std::vector<CarriedRange> carried_range(ChannelKind kind) const override {
    RegisterPlan plan;
    if (!compile_register_map(config_.map, plan).ok()) return {};
    const bool sp = kind == ChannelKind::setpoint;
    const std::vector<Codec>& codecs = sp ? plan.setpoints : plan.values;
    const std::vector<RegisterEntry>& entries = sp ? config_.map.setpoints : config_.map.values;
    std::vector<CarriedRange> out;
    for (std::size_t i = 0; i < codecs.size(); ++i) {
      const Codec& c = codecs[i];
      if (c.type == RegisterType::float32) {
        out.push_back({});
        continue;
      }
      const double count = std::abs((c.eng_max - c.eng_min) / (c.raw_max - c.raw_min));
      out.push_back(
          {true, std::min(c.eng_min, c.eng_max), std::max(c.eng_min, c.eng_max), count,
           "register " + std::to_string(entries[i].address) + " " + entries[i].type + " raw " +
               config::format_number(c.raw_min) + ".." + config::format_number(c.raw_max) + " = " +
               config::format_number(c.eng_min) + ".." + config::format_number(c.eng_max)});
    }
    return out;
  }

  [[nodiscard]] double response_timeout_s() const override {
    return config_.device.response_timeout_ms / 1000.0;
  }

  [[nodiscard]] std::string check_tick(double /*period_s*/) const override { return ""; }

 private:
  [[nodiscard]] const RegisterEntry& entry(ChannelKind kind, std::size_t i) const {
    return (kind == ChannelKind::setpoint ? config_.map.setpoints : config_.map.values).at(i);
  }

  std::string_view name_;
  ModbusConfig config_;
};

}  // namespace

std::unique_ptr<TransportConfig> make_transport_config(std::string_view name) {
  return std::make_unique<ModbusTransport>(name == "modbus-rtu" ? "modbus-rtu" : "modbus-tcp");
}

std::string format_device_keys(const ModbusDevice& d) {
  std::string out;
  if (d.transport == "rtu") {
    out = "serial_port = " + config::toml_string(d.serial_port) +
          "\nbaud = " + std::to_string(d.baud) + "\nparity = " + config::toml_string(d.parity) +
          "\ndata_bits = " + std::to_string(d.data_bits) +
          "\nstop_bits = " + std::to_string(d.stop_bits) + "\n";
  } else {
    out = "host = " + config::toml_string(d.host) + "\nport = " + std::to_string(d.port) + "\n";
  }
  return out + "unit_id = " + std::to_string(d.unit_id) +
         "\nresponse_timeout_ms = " + std::to_string(d.response_timeout_ms) + "\n";
}

const ModbusConfig* modbus_config_of(const TransportConfig& transport) noexcept {
  if (transport.name() != "modbus-tcp" && transport.name() != "modbus-rtu") return nullptr;
  return &static_cast<const ModbusTransport&>(transport).config();
}

}  // namespace excite::hal::modbus
