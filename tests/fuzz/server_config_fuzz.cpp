// SPDX-License-Identifier: MIT
// Fuzzes excite-plant's configuration (sim/server, parse_server_config), then, as
// excite-plant does at start-up, places the registers for a plant with one input per
// setpoint and one output per value (compile_layout, free-running and lock-step) and builds
// the register image. Contracts checked: errors are std::invalid_argument naming the source
// (any other exception escapes and is reported as a crash); a layout has one setpoint per
// input and one value per output, each inside its table's extent; a fresh image reads the
// input baseline back exactly, and takes the output baseline.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "check.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace {

using excite::sim::server::PlacedValue;
using excite::sim::server::ServerConfig;
using excite::sim::server::ServerLayout;
using excite::sim::server::TableExtent;

bool inside(const PlacedValue& v, const TableExtent& extent) {
  const std::uint32_t words = v.codec.type == excite::hal::modbus::RegisterType::float32 ? 2 : 1;
  return v.address >= extent.start && v.address + words <= extent.start + extent.count;
}

std::vector<double> baseline_or_zero(const std::vector<double>& baseline, std::size_t count) {
  return baseline.size() == count ? baseline : std::vector<double>(count, 0.0);
}

void check_layout(const ServerConfig& config, std::size_t inputs, std::size_t outputs,
                  bool lockstep) {
  ServerLayout layout;
  try {
    layout = excite::sim::server::compile_layout(config, static_cast<int>(inputs),
                                                 static_cast<int>(outputs), lockstep, "fuzz");
  } catch (const std::invalid_argument& e) {
    EXCITE_FUZZ_CHECK(std::string_view(e.what()).starts_with("fuzz"), "an error names the source");
    return;
  }
  EXCITE_FUZZ_CHECK(layout.setpoints.size() == inputs && layout.values.size() == outputs,
                    "one setpoint per input, one value per output");
  for (const PlacedValue& v : layout.setpoints) {
    EXCITE_FUZZ_CHECK(!v.input_table && inside(v, layout.holding), "setpoint outside the table");
  }
  for (const PlacedValue& v : layout.values) {
    EXCITE_FUZZ_CHECK(inside(v, v.input_table ? layout.input : layout.holding),
                      "value outside its table");
  }
  const auto u0 = baseline_or_zero(config.plant.input_baseline, inputs);
  const auto y0 = baseline_or_zero(config.plant.output_baseline, outputs);
  excite::sim::server::RegisterImage image(layout, u0, y0);
  std::vector<double> u(inputs, -1.0);
  image.read_setpoints(u.data());
  EXCITE_FUZZ_CHECK(u == u0, "a fresh image reads the input baseline back");
  image.write_values(y0.data());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  ServerConfig config;
  try {
    config = excite::sim::server::parse_server_config(text, "fuzz-plant.toml");
  } catch (const std::invalid_argument& e) {
    EXCITE_FUZZ_CHECK(std::string_view(e.what()).starts_with("fuzz-plant.toml"),
                      "an error names the source");
    return 0;
  }
  const std::size_t inputs = config.registers.map.setpoints.size();
  const std::size_t outputs = config.registers.map.values.size();
  if (inputs == 0 || outputs == 0) return 0;  // excite-plant then uses the default map
  check_layout(config, inputs, outputs, false);
  check_layout(config, inputs, outputs, true);
  return 0;
}
