// SPDX-License-Identifier: MIT
// One tick's Modbus TCP exchange on loopback — write 4 float setpoints and a heartbeat
// (one FC16 of 9 registers), read 4 float values (one FC04 of 8 registers) — through
// ModbusFieldBus, against a bare libmodbus loop doing the same exchange with the same
// server in the same process. Prints both and the field bus's overhead ratio
// (target <= 10 %). The machine is shared, so each benchmark runs in repetitions,
// randomly interleaved, and the medians are compared: wall time (what a tick waits) and
// the client thread's CPU time (the cost our code adds; the server thread is excluded).
#include <benchmark/benchmark.h>
#include <modbus.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "fault_server.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

namespace {

excite::test::FaultServer* server = nullptr;

void field_bus_exchange(benchmark::State& state) {
  using namespace excite::hal::modbus;
  ModbusConfig config;
  config.device.port = server->port();
  config.device.response_timeout_ms = 2000;
  for (std::uint32_t i = 0; i < 4; ++i) {
    config.map.setpoints.push_back(RegisterEntry{"sp", 2 * i, 16, "float32", "ABCD", 0, 0, {}, {}});
    config.map.values.push_back(
        RegisterEntry{"pv", 100 + 2 * i, 4, "float32", "ABCD", 0, 0, {}, {}});
  }
  config.map.heartbeat_address = 8;
  ModbusFieldBus bus;
  if (const auto v = bus.configure(config); !v.ok()) {
    state.SkipWithError(v.message().c_str());
    return;
  }
  std::array<double, 4> setpoints{1.0, 2.0, 3.0, 4.0};
  std::array<double, 4> values{};
  std::uint16_t heartbeat = 0;
  for (auto _ : state) {
    setpoints[0] += 1.0;
    if (bus.exchange(setpoints, ++heartbeat, values) != excite::hal::StatusCode::ok) {
      state.SkipWithError(bus.detail());
      break;
    }
    benchmark::DoNotOptimize(values);
  }
}

void bare_libmodbus_exchange(benchmark::State& state) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", server->port());
  modbus_set_response_timeout(ctx, 2, 0);
  if (modbus_connect(ctx) == -1) {
    state.SkipWithError(modbus_strerror(errno));
    modbus_free(ctx);
    return;
  }
  std::array<float, 4> setpoints{1.0F, 2.0F, 3.0F, 4.0F};
  std::array<float, 4> values{};
  std::array<std::uint16_t, 9> out{};
  std::array<std::uint16_t, 8> in{};
  std::uint16_t heartbeat = 0;
  for (auto _ : state) {
    setpoints[0] += 1.0F;
    for (std::size_t i = 0; i < 4; ++i) {
      modbus_set_float_abcd(setpoints[i], &out[2 * i]);
    }
    out[8] = ++heartbeat;
    if (modbus_write_registers(ctx, 0, 9, out.data()) == -1 ||
        modbus_read_input_registers(ctx, 100, 8, in.data()) == -1) {
      state.SkipWithError(modbus_strerror(errno));
      break;
    }
    for (std::size_t i = 0; i < 4; ++i) {
      values[i] = modbus_get_float_abcd(&in[2 * i]);
    }
    benchmark::DoNotOptimize(values);
  }
  modbus_close(ctx);
  modbus_free(ctx);
}

struct Samples {
  std::vector<double> wall_us;
  std::vector<double> cpu_us;
};

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

// Keeps every repetition's mean time per iteration (us) as it is reported.
class RecordingReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Iteration && !run.error_occurred) {
        Samples& samples = results[run.run_name.function_name];
        samples.wall_us.push_back(run.GetAdjustedRealTime());
        samples.cpu_us.push_back(run.GetAdjustedCPUTime());
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, Samples> results;
};

}  // namespace

BENCHMARK(bare_libmodbus_exchange)->Unit(benchmark::kMicrosecond)->Repetitions(9);
BENCHMARK(field_bus_exchange)->Unit(benchmark::kMicrosecond)->Repetitions(9);

int main(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  std::string interleave = "--benchmark_enable_random_interleaving=true";
  args.push_back(interleave.data());
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  excite::test::FaultServer fault_server;
  server = &fault_server;
  RecordingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const auto bare = reporter.results.find("bare_libmodbus_exchange");
  const auto ours = reporter.results.find("field_bus_exchange");
  if (bare == reporter.results.end() || ours == reporter.results.end()) {
    std::fprintf(stderr, "missing a result: no ratio\n");
    return 1;
  }
  const double bare_wall = median(bare->second.wall_us);
  const double ours_wall = median(ours->second.wall_us);
  const double bare_cpu = median(bare->second.cpu_us);
  const double ours_cpu = median(ours->second.cpu_us);
  std::printf(
      "one tick (4 float setpoints + heartbeat, 4 float values), Modbus TCP on loopback,\n"
      "median of %zu interleaved repetitions (target overhead <= 10 %%):\n"
      "  wall time   bare libmodbus %7.2f us  field bus %7.2f us  overhead %+6.1f %%\n"
      "  client CPU  bare libmodbus %7.2f us  field bus %7.2f us  overhead %+6.1f %%\n",
      ours->second.wall_us.size(), bare_wall, ours_wall, 100.0 * (ours_wall / bare_wall - 1.0),
      bare_cpu, ours_cpu, 100.0 * (ours_cpu / bare_cpu - 1.0));
  benchmark::Shutdown();
  return 0;
}
