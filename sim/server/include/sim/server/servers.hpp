// SPDX-License-Identifier: MIT
#pragma once
// The table of excite-plant's servers, looked up by transport name. It mirrors the gateway's
// table (hal/transports) and uses the same names as the gateway's [device] transport. The
// command line names a transport, main looks it up here, and main never chooses a server
// itself. A new transport is a new server plus its row in servers.cpp.

#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "sim/server/closed_loop.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/plant_server.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {

/// What every server is given; each takes what its transport needs.
struct Serving {
  PlantProcess& process;
  RegisterImage& image;         // the register image (Modbus)
  const ServerLayout& layout;   // its layout (Modbus)
  const ServeOptions& options;  // transport settings, clock, run log, faults
  bool default_map = false;     // the register map derived from the plant (no --config)
  std::string interface;        // the SocketCAN interface (CAN)
  ClosedLoop* loop = nullptr;   // the controller in the loop; null: open loop
  std::function<void()> ready;  // called once the server listens (signal handlers)
  std::function<bool()> stop;   // polled: true ends serving
};

struct ServerEntry {
  std::string_view name;         // the gateway's [device] transport: "modbus-tcp", "can"
  std::string_view option;       // excite-plant's option that selects it: "--modbus-tcp"
  std::string_view closed_loop;  // "": it serves a controller's registers; else why not
  int (*serve)(const Serving&);  // excite-plant's exit code (serve_modbus, serve_can)
};

/// Every server, the default (Modbus TCP) first.
std::span<const ServerEntry> servers() noexcept;

/// The server called `name`, or null.
const ServerEntry* find_server(std::string_view name) noexcept;

/// The options of the servers that serve a closed loop: "--modbus-tcp or --modbus-rtu".
std::string closed_loop_options();

}  // namespace excite::sim::server
