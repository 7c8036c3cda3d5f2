// SPDX-License-Identifier: MIT
#pragma once
// The gateway component against the in-process simlink plant (alatiqi4x4): the plan file
// and the GatewayConfig shared by the integration fixture (gateway_fixture.hpp) and the
// benches (tests/bench/engine), so no test wires the gateway by hand.
//
// Values, in the simlink bus's order: [0, 4) outputs, [4, 8) readbacks, 8 heartbeat echo,
// 9 command register (SimLinkConfig::command_register = true).

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "../../unit/plan/example_plan.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/plan/codec.hpp"

namespace excite::testing {

inline constexpr std::uint32_t kInputs = 4;
inline constexpr std::uint32_t kOutputs = 4;
inline constexpr std::uint32_t kEcho = 8;
inline constexpr std::uint32_t kCommand = 9;
inline constexpr double kU0[kInputs] = {50.0, 60.0, 70.0, 80.0};
inline constexpr double kY0[kOutputs] = {0.9, 0.1, 0.5, 0.3};
inline constexpr double kTestBand = 1000.0;  // test limits y0 ± band: never hit by the plan

/// The example plan (T = 1 min, 4080 rows), lengthened to `rows` when that is more (the
/// excitation is zero after its sources' windows), as the bytes of a plan file.
inline std::vector<std::uint8_t> example_plan_file(std::uint32_t rows = 0) {
  auto p = plan::testing::example_plan();
  if (rows > p->recipe.samples) p->recipe.samples = rows;
  std::vector<std::uint8_t> bytes(plan::max_encoded_size());
  const plan::EncodeResult encoded = plan::encode(*p, bytes);
  if (!encoded.status) {
    std::fprintf(stderr, "example plan: %s\n", encoded.status.message());
    std::abort();
  }
  bytes.resize(encoded.size);
  return bytes;
}

struct SimlinkGatewayOptions {
  std::size_t ring_records = 8192;
  double limit = 20.0;      // setpoint limits u0 ± limit
  double max_move = 5.0;    // per tick
  bool test_limits = true;  // outputs: y0 ± kTestBand, hysteresis 10
  double tick_s =
      60.0;  // the tick period (the plan's T, or period_s); durations are in ticks of it
  std::uint32_t ramp_ticks = 5;
  std::optional<double> period_s;  // gateway.period_s (compressed time), if set
};

/// The gateway configuration matching the simlink plant's value layout (as the TOML parser
/// would build it): ramp 5 ticks, dwell 10, suspension timeout 200, heartbeat lag 3.
inline app::GatewayConfig simlink_config(const SimlinkGatewayOptions& o) {
  app::GatewayConfig c;
  c.source = "simlink gateway";
  c.plant = "alatiqi4x4 (simlink)";
  c.simulator = true;  // the bus is handed over built; no [device] is opened
  c.period_s = o.period_s;
  c.ramp_s = o.ramp_ticks * o.tick_s;
  c.resume_dwell_s = 10 * o.tick_s;
  c.suspend_timeout_s = 200 * o.tick_s;
  c.comm_fail_limit = 3;
  c.heartbeat_max_lag_s = 3 * o.tick_s;
  c.log_ring = static_cast<std::uint32_t>(o.ring_records);
  c.realtime_priority = 0;
  const char* in[kInputs] = {"L", "V", "S", "F"};
  for (std::uint32_t i = 0; i < kInputs; ++i) {
    c.setpoints.push_back({in[i], "kmol/min", kU0[i] - o.limit, kU0[i] + o.limit, o.max_move,
                           std::string(in[i]) + "_rb"});
  }
  const char* out[kOutputs] = {"xD", "xS", "xB", "T"};
  const char* out_unit[kOutputs] = {"-", "-", "-", "K"};
  for (std::uint32_t j = 0; j < kOutputs; ++j) {
    app::ValueSpec v{out[j], out_unit[j], app::ValueRole::output, {}, {}, 0.0};
    if (o.test_limits) {
      v.test_low = kY0[j] - kTestBand;
      v.test_high = kY0[j] + kTestBand;
      v.hysteresis = 10.0;
    }
    c.values.push_back(v);
  }
  for (std::uint32_t i = 0; i < kInputs; ++i) {
    c.values.push_back(
        {std::string(in[i]) + "_rb", "kmol/min", app::ValueRole::readback, {}, {}, 0.0});
  }
  c.values.push_back({"hb_echo", "-", app::ValueRole::heartbeat_echo, {}, {}, 0.0});
  c.values.push_back({"command", "-", app::ValueRole::command, {}, {}, 0.0});
  return c;
}

}  // namespace excite::testing
