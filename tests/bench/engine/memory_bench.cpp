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

#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/realtime.hpp"
#include "firmware/app/runner.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"
#include "sim/simlink/simlink_field_bus.hpp"
#include "sim/library/library.hpp"
#include "tests/unit/plan/example_plan.hpp"

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
    bytes.resize(plan::max_encoded_size());
    const auto r = plan::encode(*plan::testing::example_plan(), bytes);
    bytes.resize(r.size);
  }
  const app::RealtimeResult rt = app::make_realtime(0);  // mlockall: the gateway's set-up
  auto p = std::make_unique<plan::Plan>();
  if (auto s = engine::load_plan(bytes, 4, signal::kTableCapacity, *p); !s) {
    std::fprintf(stderr, "%s\n", s.message());
    return 1;
  }
  std::vector<double> storage(signal::kTableCapacity);
  std::vector<double> scratch(signal::scratch_size(p->recipe));
  signal::TableView table;
  if (auto s = engine::make_table(*p, storage, scratch, table); !s) return 1;
  scratch = {};
  hal::VirtualClock clock;
  hal::simlink::SimLinkConfig sc;
  sc.input_baseline = {50, 60, 70, 80};
  sc.output_baseline = {0, 0, 0, 0};
  hal::simlink::SimLinkFieldBus bus(sim::library_plant("alatiqi4x4"), 1.0, sc, &clock);
  engine::EngineConfig ec;
  ec.inputs = 4;
  ec.values = static_cast<std::uint32_t>(bus.value_count());
  for (std::uint32_t i = 0; i < 4; ++i) {
    ec.input[i] = {sc.input_baseline[i] - 50, sc.input_baseline[i] + 50, 100,
                   bus.readback_index(i)};
  }
  auto eng = std::make_unique<engine::Engine>();
  if (!eng->configure(ec, table)) return 1;
  std::vector<engine::TickRecord> ring_storage(4096);  // the configuration's default ring
  engine::SpanLogRing ring(ring_storage);
  app::Runner runner(*eng, bus, clock, ring, std::chrono::seconds(60));
  if (!runner.arm()) return 1;
  std::printf(
      "plan: %u channels x %u samples; table storage %zu values (%zu kB); ring %zu records "
      "(%zu kB); memory locked: %s\n",
      table.channels, table.samples, storage.size(), storage.size() * 8 / 1024, ring_storage.size(),
      ring_storage.size() * sizeof(engine::TickRecord) / 1024, rt.locked ? "yes" : "no");
  print_status("after start-up");
  app::CommandMailbox commands;
  commands.post(engine::Command::start);
  engine::TickRecord sink;
  std::uint64_t ticks = 0;
  while (eng->state() != engine::State::safe) {
    ticks += runner.run(commands, nullptr, 1000).ticks;
    while (ring.pop(sink)) {
    }
  }
  std::printf("ran %llu ticks to %s\n", static_cast<unsigned long long>(ticks),
              engine::to_string(eng->state()));
  print_status("after the run");
  return 0;
}
