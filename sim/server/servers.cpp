// SPDX-License-Identifier: MIT
#include "sim/server/servers.hpp"

#include <array>

#include "sim/server/can_plant_server.hpp"

namespace excite::sim::server {

namespace {

int modbus(const Serving& s) {
  return serve_modbus(s.process, s.image, s.layout, s.options, s.default_map, s.ready, s.stop,
                      s.loop);
}

int can(const Serving& s) {
  return serve_can(s.process, s.options, s.interface, s.ready, s.stop);
}

// Modbus RTU differs from TCP only in where serve_modbus listens (options.rtu_device).
const std::array<ServerEntry, 3> kServers = {{
    {"modbus-tcp", "--modbus-tcp", "", modbus},
    {"modbus-rtu", "--modbus-rtu", "", modbus},
    {"can", "--can", "the CAN frame map has no closed-loop frames", can},
}};

}  // namespace

std::span<const ServerEntry> servers() noexcept {
  return kServers;
}

const ServerEntry* find_server(std::string_view name) noexcept {
  for (const ServerEntry& s : kServers) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string closed_loop_options() {
  std::string out;
  for (const ServerEntry& s : kServers) {
    if (!s.closed_loop.empty()) continue;
    out += (out.empty() ? "" : " or ") + std::string(s.option);
  }
  return out;
}

}  // namespace excite::sim::server
