// SPDX-License-Identifier: MIT
#include "hal/can/can_transport.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "base/config/writer.hpp"
#include "hal/can/bus_timing.hpp"

namespace excite::hal::can {

namespace {

std::string hex(unsigned id, const char* form = "0x%X") {
  char text[16];
  std::snprintf(text, sizeof text, form, id);
  return text;
}

std::string counts_of(const CanFieldBus& can) {
  const CanCounters c = can.counters();
  std::string out = "can " + can.interface_name() + ": value frames refused for their DLC " +
                    std::to_string(c.short_frames);
  if (c.short_frames > 0) {
    out += " (first " + hex(c.first_short_id) + " DLC " + std::to_string(c.first_short_dlc) + ")";
  }
  out += ", frames of the gateway's own identifiers from another node " +
         std::to_string(c.own_id_frames);
  if (c.own_id_frames > 0) out += " (first " + hex(c.first_own_id) + ")";
  out += ", sends refused " + std::to_string(c.send_failures);
  if (c.send_failures > 0) out += std::string(" (last: ") + std::strerror(c.last_send_error) + ")";
  out += ", reads with a value frame stale or missing " + std::to_string(c.stale_reads) +
         ", echoes missing " + std::to_string(c.echo_timeouts) + ", error frames " +
         std::to_string(c.error_frames);
  return out;
}

class CanTransport final : public TransportConfig {
 public:
  [[nodiscard]] std::string_view name() const noexcept override { return "can"; }
  [[nodiscard]] const CanConfig& config() const noexcept { return config_; }

  // The CAN device is the [can] section.
  [[nodiscard]] std::vector<std::string> device_keys() const override { return {}; }
  void read_device(const config::Table& /*device*/) override {}

  [[nodiscard]] std::vector<std::string> sections() const override { return {"can"}; }

  // [can]: interface, timeouts and the heartbeat's place in a setpoint frame.
  void read_sections(const config::Table& root) override {
    const toml::node* n = root.get("can");
    if (n == nullptr) throw config::Error("[can]", "(missing)", "a table with transport = \"can\"");
    if (!n->is_table()) throw config::Error("can", config::describe(*n), "a table [can]");
    const config::Table t(*n->as_table(), "can", root.source());
    t.only_keys({"bitrate", "enobufs_limit", "heartbeat_byte_offset", "heartbeat_byte_order",
                 "heartbeat_extended", "heartbeat_id", "heartbeat_type", "interface",
                 "value_timeout_ms"});
    CanConfig& c = config_;
    auto iface = t.text("interface");
    if (!iface)
      throw config::Error("can.interface", "(missing)", "a SocketCAN interface, e.g. can0");
    c.interface = *iface;
    if (auto v = t.integer("value_timeout_ms", 0, 1 << 30)) {
      c.value_timeout_ms = static_cast<std::int32_t>(*v);
    }
    if (auto v = t.integer("enobufs_limit", 0, 1 << 30)) {
      c.enobufs_limit = static_cast<std::uint32_t>(*v);
    }
    if (auto v = t.integer("bitrate", 10000, 1000000)) {  // classic CAN: up to 1 Mbit/s
      c.bitrate = static_cast<std::uint32_t>(*v);
    }
    if (auto id = t.integer("heartbeat_id", 0, 0x1FFFFFFF)) {
      CanSignal hb;
      hb.name = "heartbeat";
      hb.id = static_cast<std::uint32_t>(*id);
      hb.extended = t.flag("heartbeat_extended").value_or(false);
      hb.byte_offset =
          static_cast<std::uint32_t>(t.integer("heartbeat_byte_offset", 0, 7).value_or(0));
      hb.type = t.text("heartbeat_type").value_or("uint16");
      hb.byte_order = t.text("heartbeat_byte_order").value_or("little");
      c.map.heartbeat = hb;
    } else {
      for (const char* key : {"heartbeat_extended", "heartbeat_byte_offset", "heartbeat_type",
                              "heartbeat_byte_order"}) {
        if (const toml::node* k = t.get(key)) {
          throw config::Error(std::string("can.") + key, config::describe(*k),
                              "heartbeat_id as well");
        }
      }
    }
    if (const toml::node* m = root.get("map")) {
      throw config::Error("map", config::describe(*m),
                          "no [map] with transport = \"can\" (the heartbeat is can.heartbeat_id)");
    }
  }

  [[nodiscard]] std::vector<std::string> entry_keys() const override {
    return {"can_id", "extended", "byte_offset", "type", "byte_order", "scale", "offset"};
  }

  void read_entry(const config::Table& t, ChannelKind kind, const std::string& name) override {
    CanSignal s;
    s.name = name;
    auto id = t.integer("can_id", 0, 0x1FFFFFFF);
    if (!id) throw config::Error(t.field("can_id"), "(missing)", "a CAN identifier (e.g. 0x210)");
    s.id = static_cast<std::uint32_t>(*id);
    s.extended = t.flag("extended").value_or(false);
    s.byte_offset = static_cast<std::uint32_t>(t.integer("byte_offset", 0, 7).value_or(0));
    if (auto v = t.text("type")) s.type = *v;
    if (auto v = t.text("byte_order")) s.byte_order = *v;
    if (auto v = t.number("scale")) s.scale = *v;
    if (auto v = t.number("offset")) s.offset = *v;
    (kind == ChannelKind::setpoint ? config_.map.setpoints : config_.map.values).push_back(s);
  }

  void validate() const override {
    config::Check v = can::validate(config_);
    if (v.ok()) return;
    // The frame map names its fields; the file spells them can_id and [can].heartbeat_*.
    if (v.field.rfind("heartbeat.", 0) == 0) {
      v.field = "can.heartbeat_" + v.field.substr(10);
    } else if (v.field.size() > 3 && v.field.compare(v.field.size() - 3, 3, ".id") == 0) {
      v.field = v.field.substr(0, v.field.size() - 3) + ".can_id";
    }
    throw config::Error(v);
  }

  // Setpoint and value frames never share an identifier (validate()): nothing to compare.
  void check_readback(std::size_t /*setpoint*/, std::size_t /*value*/) const override {}

  [[nodiscard]] MadeBus make_bus(const Clock& clock,
                                 std::optional<std::size_t> await_echo) const override {
    MadeBus made;
    auto bus = std::make_unique<CanFieldBus>(clock);
    CanConfig c = config_;
    c.await_echo = await_echo;
    if (const config::Check v = bus->configure(c); !v.ok()) {
      made.error = v.message();
      return made;
    }
    const CanFieldBus* counted = bus.get();
    made.counts_report = [counted] { return counts_of(*counted); };
    made.bus = std::move(bus);
    return made;
  }

  [[nodiscard]] std::string describe_peer() const override {
    return "can " + config_.interface +
           (config_.bitrate > 0 ? " " + std::to_string(config_.bitrate) + " bit/s" : "") +
           ", value frames stale after " + std::to_string(config_.value_timeout_ms) + " ms";
  }

  [[nodiscard]] std::string describe_channel(ChannelKind kind, std::size_t i) const override {
    const CanSignal& g = signal(kind, i);
    return "CAN " + hex(g.id, "0x%03X") + " byte " + std::to_string(g.byte_offset) + " " + g.type;
  }

  [[nodiscard]] std::string channel_columns(ChannelKind kind, std::size_t i) const override {
    const CanSignal& g = signal(kind, i);
    char text[128];
    if (kind == ChannelKind::setpoint) {
      std::snprintf(text, sizeof text, "CAN 0x%03X byte %u %-7s %-6s scale %g offset %g", g.id,
                    g.byte_offset, g.type.c_str(), g.byte_order.c_str(), g.scale, g.offset);
    } else {
      std::snprintf(text, sizeof text, "CAN 0x%03X byte %u %-7s", g.id, g.byte_offset,
                    g.type.c_str());
    }
    return text;
  }

  [[nodiscard]] std::string heartbeat_columns() const override {
    if (!config_.map.heartbeat) return "";
    const CanSignal& h = *config_.map.heartbeat;
    char text[64];
    std::snprintf(text, sizeof text, "CAN 0x%03X byte %u %s", h.id, h.byte_offset, h.type.c_str());
    return text;
  }

  // engineering = raw · scale + offset over the raw type's whole range; float32: unbounded.
  [[nodiscard]] std::vector<CarriedRange> carried_range(ChannelKind kind) const override {
    CanPlan plan;
    if (!compile_frame_map(config_.map, plan).ok()) return {};
    const bool sp = kind == ChannelKind::setpoint;
    const std::vector<SignalCodec>& codecs = sp ? plan.setpoints : plan.values;
    const std::vector<CanSignal>& signals = sp ? config_.map.setpoints : config_.map.values;
    std::vector<CarriedRange> out;
    for (std::size_t i = 0; i < codecs.size(); ++i) {
      const SignalCodec& c = codecs[i];
      double lo = 0.0;
      double hi = 0.0;
      if (!raw_range(c.type, lo, hi)) {
        out.push_back({});
        continue;
      }
      const double a = lo * c.scale + c.offset_eng;
      const double b = hi * c.scale + c.offset_eng;
      out.push_back({true, std::min(a, b), std::max(a, b), std::abs(c.scale),
                     "CAN " + hex(signals[i].id) + " " + signals[i].type + " scale " +
                         config::format_number(c.scale) + " offset " +
                         config::format_number(c.offset_eng)});
    }
    return out;
  }

  [[nodiscard]] double response_timeout_s() const override {
    return config_.value_timeout_ms / 1000.0;
  }

  // With a [can] bitrate: one tick's frames at their worst case (bus_timing.hpp); a virtual
  // bus (no bitrate) is not checked.
  [[nodiscard]] std::string check_tick(double period_s) const override {
    if (config_.bitrate == 0) return "";
    CanPlan plan;
    if (!compile_frame_map(config_.map, plan).ok()) return "";  // checked at load
    const config::Check v = check_tick_fits(plan, config_.bitrate, period_s);
    return v.ok() ? "" : v.message();
  }

 private:
  [[nodiscard]] const CanSignal& signal(ChannelKind kind, std::size_t i) const {
    return (kind == ChannelKind::setpoint ? config_.map.setpoints : config_.map.values).at(i);
  }

  CanConfig config_;
};

}  // namespace

std::unique_ptr<TransportConfig> make_transport_config() {
  return std::make_unique<CanTransport>();
}

const CanConfig* can_config_of(const TransportConfig& transport) noexcept {
  if (transport.name() != "can") return nullptr;
  return &static_cast<const CanTransport&>(transport).config();
}

std::string format_can_settings(const CanConfig& c) {
  using config::toml_string;
  std::string out = "interface = " + toml_string(c.interface) +
                    "\nvalue_timeout_ms = " + std::to_string(c.value_timeout_ms) +
                    "\nenobufs_limit = " + std::to_string(c.enobufs_limit) + "\n";
  if (c.bitrate != 0) out += "bitrate = " + std::to_string(c.bitrate) + "\n";
  if (const auto& hb = c.map.heartbeat) {
    out += "heartbeat_id = " + hex(hb->id) + "\n";
    if (hb->extended) out += "heartbeat_extended = true\n";
    out += "heartbeat_byte_offset = " + std::to_string(hb->byte_offset) +
           "\nheartbeat_type = " + toml_string(hb->type) +
           "\nheartbeat_byte_order = " + toml_string(hb->byte_order) + "\n";
  }
  return out;
}

std::string format_can_entry(const CanSignal& s) {
  using config::toml_number;
  using config::toml_string;
  std::string out = "can_id = " + hex(s.id) + "\n";
  if (s.extended) out += "extended = true\n";
  out += "byte_offset = " + std::to_string(s.byte_offset) + "\ntype = " + toml_string(s.type) +
         "\nbyte_order = " + toml_string(s.byte_order) + "\n";
  if (s.scale != 1.0) out += "scale = " + toml_number(s.scale) + "\n";
  if (s.offset != 0.0) out += "offset = " + toml_number(s.offset) + "\n";
  return out;
}

}  // namespace excite::hal::can
