// SPDX-License-Identifier: MIT
// Fuzzes the gateway configuration (firmware/app, parse_gateway_config) and its conversion to
// the engine's configuration (to_engine_config, then engine::validate), the path
// excite-gateway takes at start-up (Gateway::prepare). Periods: the file's period_s when it
// rounds to at least 1 ns (the gateway refuses less), else a plan sample time of 1 min, and
// 1 ms (the shortest sensible tick, so seconds → ticks conversions see large counts).
// Contracts checked: exactly one of config and error; an error names the source; a config
// converts without undefined behaviour (UBSan: float → integer overflow, array bounds);
// the engine configuration has one input per setpoint and one value per value.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "check.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/engine/config.hpp"

namespace {

void convert(const excite::app::GatewayConfig& config, std::chrono::duration<double> period) {
  const excite::engine::EngineConfig engine = excite::app::to_engine_config(config, period);
  EXCITE_FUZZ_CHECK(engine.inputs == config.setpoints.size(), "one engine input per setpoint");
  EXCITE_FUZZ_CHECK(engine.values == config.values.size(), "one engine value per value");
  // The gateway refuses an engine configuration that does not validate, by name: not a
  // crash, but the message must say why.
  const excite::engine::Status status = excite::engine::validate(engine);
  EXCITE_FUZZ_CHECK(status.is_ok() || std::string_view(status.message()).size() > 0,
                    "an engine refusal names its reason");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view source = "fuzz-gateway.toml";
  const excite::app::ConfigResult result = excite::app::parse_gateway_config(text, source);
  EXCITE_FUZZ_CHECK(result.config.has_value() == result.error.empty(),
                    "exactly one of config and error");
  if (!result.config) {
    EXCITE_FUZZ_CHECK(std::string_view(result.error).starts_with(source),
                      "an error starts with the source name");
    return 0;
  }
  const excite::app::GatewayConfig& config = *result.config;
  using Seconds = std::chrono::duration<double>;
  const Seconds file_period = config.period_s ? Seconds(*config.period_s) : Seconds(60.0);
  if (std::chrono::round<std::chrono::nanoseconds>(file_period).count() > 0) {
    convert(config, file_period);
  }
  convert(config, Seconds(0.001));
  return 0;
}
