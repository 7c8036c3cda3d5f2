// SPDX-License-Identifier: MIT
// fuzz_make_seeds OUT_DIR: writes the generated seed corpora, the project's own outputs:
//   OUT_DIR/plan_decode_fuzz/   plan files as `excite design` writes them (every preset of
//                               Table 6.1 for the alatiqi4x4 case study, a plain multisine)
//   OUT_DIR/runlog_reader_fuzz/ run logs as `excite simulate` writes them (one plan, a step)
//   OUT_DIR/plant_toml_fuzz/    every library plant as a plant file (sim/library)
//   OUT_DIR/element_fuzz/       every element of those plants, as text
//   OUT_DIR/modbus_request_fuzz/ requests to the register map of
//                               sim/server/examples/alatiqi4x4.toml, in the harness's framing
//                               (a length byte, then the PDU)
// The text seeds written by hand stay in the tree (tests/fuzz/seeds/).

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/library/library.hpp"
#include "sim/plants/plant.hpp"

namespace {

namespace fs = std::filesystem;
using namespace excite;

void write_text(const fs::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void plans_and_logs(const fs::path& out) {
  const fs::path plans = out / "plan_decode_fuzz";
  const fs::path logs = out / "runlog_reader_fuzz";
  fs::create_directories(plans);
  fs::create_directories(logs);
  const host::PriorKnowledge prior = host::case_study("alatiqi4x4");
  constexpr std::uint64_t created = 0;  // reproducible bytes
  for (const host::PresetInfo& preset : host::presets()) {
    const host::Design design = host::design_preset(prior, preset, created);
    host::write_plan_file(*design.plan, plans / (std::string(preset.acronym) + ".plan"));
  }
  host::PlainMultisine multisine;
  multisine.period = 64;
  multisine.first_line = 1;
  multisine.last_line = 15;
  const host::Design plain = host::design_plain_multisine(prior, multisine, created);
  host::write_plan_file(*plain.plan, plans / "multisine.plan");

  // Run logs: the plain multisine through the plant, and a step (short: seeds stay small).
  const auto plant = sim::make_plant("alatiqi4x4");
  host::SimulatedRun run = host::simulate_plan(*plain.plan, "multisine.plan", *plant, {});
  run.producer = "excite simulate (fuzz seed)";
  host::write_run_log(run, logs / "multisine.csv");
  const auto step_plant = sim::make_plant("woodberry2x2");
  host::SimulatedRun step = host::simulate_step(*step_plant, "u1", 1.0, 16, 1.0, {});
  step.producer = "excite simulate (fuzz seed)";
  host::write_run_log(step, logs / "step.csv");
}

void plants_and_elements(const fs::path& out) {
  const fs::path plants = out / "plant_toml_fuzz";
  const fs::path elements = out / "element_fuzz";
  fs::create_directories(plants);
  fs::create_directories(elements);
  int element = 0;
  for (const std::string& name : sim::library_plant_names()) {
    write_text(plants / (name + ".toml"), sim::library_plant_toml(name));
    const sim::TransferMatrix g = sim::library_plant(name);
    for (int o = 0; o < g.outputs(); ++o) {
      for (int i = 0; i < g.inputs(); ++i) {
        const std::string& text = g.element(o, i).text();
        if (!text.empty()) write_text(elements / (std::to_string(element++) + ".txt"), text);
      }
    }
  }
}

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Setpoints u1..u4 at 100 (float32 CDAB), 102 (ABCD), 104 (BADC), 106 (int16, 0..100 ↔
// 0..27648), heartbeat 108, values 200..207 (FC04 and FC03), echo 300 (FC04), command 301,
// control block 400..407; input limits [8, 12], [18, 22], [28, 32], [38, 42].
void modbus_requests(const fs::path& out) {
  const fs::path dir = out / "modbus_request_fuzz";
  fs::create_directories(dir);
  using Bytes = std::vector<std::uint8_t>;
  const Bytes read_setpoints = {5, 0x03, 0x00, 0x64, 0x00, 0x09};
  const Bytes read_values = {5, 0x04, 0x00, 0xC8, 0x00, 0x08};
  const Bytes heartbeat = {5, 0x06, 0x00, 0x6C, 0x00, 0x01};
  // u1 = 10.5 (0x41280000, CDAB), u2 = 21 (0x41A80000), u3 = 30 (0x41F00000, BADC),
  // u4 = 40 (raw 11059), 107 unused, heartbeat 2: the gateway's one FC16 per tick.
  const Bytes tick = {24,   0x10, 0x00, 0x64, 0x00, 0x09, 0x12, 0x00, 0x00, 0x41, 0x28, 0x41, 0xA8,
                      0x00, 0x00, 0xF0, 0x41, 0x00, 0x00, 0x2B, 0x33, 0x00, 0x00, 0x00, 0x02};
  const Bytes u2_too_high = {10, 0x10, 0x00, 0x66, 0x00, 0x02, 0x04, 0x42, 0xC8, 0x00, 0x00};
  const Bytes u1_low_half = {5, 0x06, 0x00, 0x65, 0x41, 0x20};
  const Bytes control = {8, 0x10, 0x01, 0x90, 0x00, 0x01, 0x02, 0x00, 0x05};
  const Bytes not_served = {4, 0x2B, 0x0E, 0x01, 0x00};
  write_bytes(dir / "read-setpoints.bin", read_setpoints);
  write_bytes(dir / "read-values.bin", read_values);
  write_bytes(dir / "heartbeat.bin", heartbeat);
  write_bytes(dir / "u2-too-high.bin", u2_too_high);
  write_bytes(dir / "control.bin", control);
  write_bytes(dir / "not-served.bin", not_served);
  Bytes session;
  for (const Bytes* frame : {&tick, &read_setpoints, &u1_low_half, &read_values, &heartbeat}) {
    session.insert(session.end(), frame->begin(), frame->end());
  }
  write_bytes(dir / "session.bin", session);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds OUT_DIR\n";
    return 2;
  }
  try {
    plans_and_logs(argv[1]);
    plants_and_elements(argv[1]);
    modbus_requests(argv[1]);
  } catch (const std::exception& e) {
    std::cerr << "fuzz_make_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
