// SPDX-License-Identifier: MIT
// Resident memory of the engine for the 4×4 case-study plan: VmRSS and VmHWM from
// /proc/self/status after start-up (plan decoded, table in the gateway's fixed storage of
// kTableCapacity values, ring allocated, memory locked when permitted) and after a run of
// the whole plan on the simlink plant (virtual clock).
//
//   tests/bench/engine/engine_memory_bench [--plan FILE]   (default: the example plan)
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "../../integration/engine/simlink_gateway.hpp"
#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/gateway.hpp"
#include "firmware/app/realtime.hpp"
#include "sim/library/library.hpp"
#include "sim/simlink/simlink_field_bus.hpp"

namespace {

void print_status(const char* when) {
  std::ifstream in("/proc/self/status");
  std::string line;
  std::string rss;
  std::string hwm;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) rss = line.substr(line.find_first_not_of(" \t", 6));
    if (line.rfind("VmHWM:", 0) == 0) hwm = line.substr(line.find_first_not_of(" \t", 6));
  }
  std::printf("%-28s VmRSS %s   VmHWM %s\n", when, rss.c_str(), hwm.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace excite;
  print_status("process start");
  std::vector<std::uint8_t> bytes;
  if (argc > 2 && std::string(argv[1]) == "--plan") {
    std::ifstream f(argv[2], std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  } else {
    bytes = testing::example_plan_file();
  }
  const app::RealtimeResult rt = app::make_realtime(0);  // mlockall: the gateway's set-up
  // The gateway component exactly as excite-gateway builds it (configuration → plan →
  // table → engine → arm); only the bus (simlink plant) and the clock (virtual) differ.
  testing::SimlinkGatewayOptions options;
  options.ring_records = 4096;  // the configuration's default ring
  options.limit = 50.0;
  options.max_move = 100.0;
  options.test_limits = false;
  app::Gateway gw(testing::simlink_config(options));
  if (auto e = gw.load_plan(bytes, argc > 2 ? argv[2] : "example plan")) {
    std::fprintf(stderr, "%s\n", e->message.c_str());
    return 1;
  }
  hal::VirtualClock clock;
  sim::simlink::SimLinkConfig sc;
  sc.input_baseline.assign(testing::kU0, testing::kU0 + testing::kInputs);
  sc.output_baseline = {0, 0, 0, 0};
  sc.command_register = true;
  sim::simlink::SimLinkFieldBus bus(sim::library_plant("alatiqi4x4"), gw.sample_time().count(), sc,
                                    &clock);
  if (auto e = gw.arm(bus, clock)) {
    std::fprintf(stderr, "%s\n", e->message.c_str());
    return 1;
  }
  const signal::ConstTableView table = gw.table();
  std::printf(
      "plan: %u channels x %u samples; table storage %zu values (%zu kB); ring %zu records "
      "(%zu kB); memory locked: %s\n",
      table.channels, table.samples, signal::kTableCapacity, signal::kTableCapacity * 8 / 1024,
      options.ring_records, options.ring_records * sizeof(engine::TickRecord) / 1024,
      rt.locked ? "yes" : "no");
  print_status("after start-up");
  app::CommandMailbox commands;
  commands.post(engine::Command::start);
  engine::TickRecord sink;
  std::uint64_t ticks = 0;
  engine::LogRingBase& ring = gw.log_ring();  // drained here, between batches
  while (gw.engine().state() != engine::State::safe) {
    ticks += gw.run(commands, nullptr, 1000).ticks;
    while (ring.pop(sink)) {
    }
  }
  std::printf("ran %llu ticks to %s\n", static_cast<unsigned long long>(ticks),
              engine::to_string(gw.engine().state()));
  print_status("after the run");
  return 0;
}
