// SPDX-License-Identifier: MIT
#include "sim/server/server_layout.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "base/config/error.hpp"

namespace excite::sim::server {
namespace {

[[noreturn]] void fail(std::string_view source, const std::string& field, const std::string& value,
                       const std::string& expected) {
  throw config::Error(source, {}, field, value, expected);
}

// One block of registers in one table, named by its configuration field.
struct Block {
  std::string field;
  std::uint32_t address;
  std::uint32_t size;
};

void check_overlaps(std::vector<Block> blocks, std::string_view source) {
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const Block& a, const Block& b) { return a.address < b.address; });
  for (std::size_t i = 1; i < blocks.size(); ++i) {
    const Block& previous = blocks[i - 1];
    const Block& block = blocks[i];
    if (previous.address + previous.size > block.address) {
      fail(source, block.field, std::to_string(block.address),
           "no overlap with " + previous.field + " (registers " + std::to_string(previous.address) +
               ".." + std::to_string(previous.address + previous.size - 1) + ")");
    }
  }
}

TableExtent extent_of(const std::vector<Block>& blocks) {
  if (blocks.empty()) return {};
  std::uint32_t lo = blocks.front().address;
  std::uint32_t hi = 0;
  for (const Block& b : blocks) {
    lo = std::min(lo, b.address);
    hi = std::max(hi, b.address + b.size);
  }
  return {lo, hi - lo};
}

// Compiles with hal and collects the blocks of both tables.
void compile(const ServerRegisters& regs, std::string_view source, hal::modbus::RegisterPlan& plan,
             std::vector<Block>& holding, std::vector<Block>& input) {
  if (const auto v = hal::modbus::compile_register_map(regs.map, plan); !v.ok()) {
    // hal names fields relative to the map; here the map is the [registers] table.
    std::string expected = v.expected;
    for (const std::string name : {"setpoints[", "values[", "heartbeat_address"}) {
      const std::string with = "with " + name;
      if (const auto at = expected.find(with); at != std::string::npos) {
        expected.insert(at + 5, "registers.");
      }
    }
    fail(source, "registers." + v.field, v.value, expected);
  }
  for (std::size_t i = 0; i < regs.map.setpoints.size(); ++i) {
    holding.push_back({"registers.setpoints[" + std::to_string(i) + "].address",
                       regs.map.setpoints[i].address,
                       hal::modbus::register_count(plan.setpoints[i].type)});
  }
  holding.push_back({"registers.heartbeat_address", *regs.map.heartbeat_address, 1});
  for (std::size_t i = 0; i < regs.map.values.size(); ++i) {
    auto& table = regs.map.values[i].function_code == 4 ? input : holding;
    table.push_back({"registers.values[" + std::to_string(i) + "].address",
                     regs.map.values[i].address, hal::modbus::register_count(plan.values[i].type)});
  }
  auto& echo_table = regs.heartbeat_echo_function_code == 4 ? input : holding;
  echo_table.push_back({"registers.heartbeat_echo_address", regs.heartbeat_echo_address, 1});
  if (regs.control_address) {
    holding.push_back({"registers.control_address", *regs.control_address, control_block_size});
  }
  if (regs.command_address) {
    holding.push_back({"registers.command_address", *regs.command_address, 1});
  }
  check_overlaps(holding, source);
  check_overlaps(input, source);
}

// A float32 ABCD (or uint16) value at `address` of one table.
PlacedValue placed(std::uint32_t address, bool input_table, bool uint16 = false) {
  hal::modbus::Codec codec;
  if (uint16) {
    codec.type = hal::modbus::RegisterType::uint16;
    codec.eng_min = 0.0;
    codec.eng_max = 65535.0;
  }
  return {codec, address, input_table};
}

// The closed-loop blocks: required with a controller, refused without one; placed, and added
// to the tables' blocks (their overlaps are checked by the caller).
std::optional<ClosedLoopLayout> place_closed_loop(const ServerConfig& config, int n, int m,
                                                  std::string_view source,
                                                  std::vector<Block>& holding,
                                                  std::vector<Block>& input) {
  const ServerRegisters& regs = config.registers;
  const std::pair<const char*, const std::optional<std::uint32_t>*> keys[] = {
      {"registers.offset_address", &regs.offset_address},
      {"registers.controller_address", &regs.controller_address},
      {"registers.controller_switch_address", &regs.controller_switch_address}};
  if (config.plant.controller.empty()) {
    for (const auto& [field, value] : keys) {
      if (value->has_value()) {
        fail(source, field, std::to_string(**value),
             "a controller to serve the closed-loop registers (plant.controller or "
             "--controller FILE), or no such key");
      }
    }
    return std::nullopt;
  }
  for (const auto& [field, value] : keys) {
    if (!value->has_value()) fail(source, field, "(missing)", "an address under a controller");
  }
  const std::uint32_t w = *regs.offset_address;
  const std::uint32_t r = *regs.controller_address;
  const std::uint32_t s = *regs.controller_switch_address;
  const std::uint32_t nu = static_cast<std::uint32_t>(n);
  const std::uint32_t mu = static_cast<std::uint32_t>(m);
  if (w + offset_block_size(n, m) > 65536) {
    fail(source, "registers.offset_address", std::to_string(w),
         "room for " + std::to_string(offset_block_size(n, m)) + " registers below 65536");
  }
  if (r + controller_block_size(n, m) > 65536) {
    fail(source, "registers.controller_address", std::to_string(r),
         "room for " + std::to_string(controller_block_size(n, m)) + " registers below 65536");
  }
  ClosedLoopLayout loop;
  for (std::uint32_t i = 0; i < nu; ++i) {
    loop.mv_offsets.push_back(placed(w + 2 * i, false));
    loop.moves.push_back(placed(r + 2 * i, true));
    loop.applied.push_back(placed(r + 2 * nu + 2 * i, true));
    loop.status.push_back(placed(r + 4 * nu + 2 * mu + i, true, true));
  }
  for (std::uint32_t j = 0; j < mu; ++j) {
    loop.sp_offsets.push_back(placed(w + 2 * nu + 2 * j, false));
    loop.setpoints.push_back(placed(r + 4 * nu + 2 * j, true));
  }
  loop.mode = placed(r + 5 * nu + 2 * mu, true, true);
  loop.controller_switch = placed(s, false, true);
  loop.offset_start = w;
  loop.offset_count = offset_block_size(n, m);
  holding.push_back({"registers.offset_address", w, loop.offset_count});
  holding.push_back({"registers.controller_switch_address", s, 1});
  input.push_back({"registers.controller_address", r, controller_block_size(n, m)});
  return loop;
}

}  // namespace

void check_registers(const ServerRegisters& registers, std::string_view source) {
  if (!registers.map.heartbeat_address) {
    fail(source, "registers.heartbeat_address", "(missing)", "a holding register address");
  }
  hal::modbus::RegisterPlan plan;
  std::vector<Block> holding;
  std::vector<Block> input;
  compile(registers, source, plan, holding, input);
}

ServerLayout compile_layout(const ServerConfig& config, int inputs, int outputs, bool lockstep,
                            std::string_view source) {
  const ServerRegisters& regs = config.registers;
  if (!regs.map.heartbeat_address) {
    fail(source, "registers.heartbeat_address", "(missing)", "a holding register address");
  }
  hal::modbus::RegisterPlan plan;
  std::vector<Block> holding;
  std::vector<Block> input;
  compile(regs, source, plan, holding, input);

  const auto count = [](std::size_t n) { return std::to_string(n); };
  if (regs.map.setpoints.size() != static_cast<std::size_t>(inputs)) {
    fail(source, "registers.setpoints", count(regs.map.setpoints.size()) + " entries",
         count(static_cast<std::size_t>(inputs)) + " (one per plant input, in plant order)");
  }
  if (regs.map.values.size() != static_cast<std::size_t>(outputs)) {
    fail(source, "registers.values", count(regs.map.values.size()) + " entries",
         count(static_cast<std::size_t>(outputs)) + " (one per plant output, in plant order)");
  }
  const PlantSettings& plant = config.plant;
  if (!plant.input_baseline.empty() &&
      plant.input_baseline.size() != static_cast<std::size_t>(inputs)) {
    fail(source, "plant.input_baseline", count(plant.input_baseline.size()) + " values",
         count(static_cast<std::size_t>(inputs)) + " (one per plant input)");
  }
  if (!plant.output_baseline.empty() &&
      plant.output_baseline.size() != static_cast<std::size_t>(outputs)) {
    fail(source, "plant.output_baseline", count(plant.output_baseline.size()) + " values",
         count(static_cast<std::size_t>(outputs)) + " (one per plant output)");
  }
  if (plant.noise_variance.size() > 1 &&
      plant.noise_variance.size() != static_cast<std::size_t>(outputs)) {
    fail(source, "plant.noise_variance", count(plant.noise_variance.size()) + " values",
         "one value, or " + count(static_cast<std::size_t>(outputs)) + " (one per plant output)");
  }
  const std::optional<ClosedLoopLayout> loop =
      place_closed_loop(config, inputs, outputs, source, holding, input);
  check_overlaps(holding, source);
  check_overlaps(input, source);
  if (lockstep && loop && loop->offset_start + loop->offset_count > *regs.map.heartbeat_address) {
    fail(source, "registers.heartbeat_address", std::to_string(*regs.map.heartbeat_address),
         "above every test-offset register in lock-step mode (registers.offset_address = " +
             std::to_string(loop->offset_start) + ", " + std::to_string(loop->offset_count) +
             " registers), so the heartbeat is written last");
  }
  if (lockstep) {
    for (std::size_t i = 0; i < regs.map.setpoints.size(); ++i) {
      if (regs.map.setpoints[i].address > *regs.map.heartbeat_address) {
        fail(source, "registers.heartbeat_address", std::to_string(*regs.map.heartbeat_address),
             "above every setpoint register in lock-step mode (registers.setpoints[" +
                 std::to_string(i) +
                 "].address = " + std::to_string(regs.map.setpoints[i].address) +
                 "), so the heartbeat is written last");
      }
    }
  }

  ServerLayout layout;
  for (std::size_t i = 0; i < regs.map.setpoints.size(); ++i) {
    layout.setpoints.push_back({plan.setpoints[i], regs.map.setpoints[i].address, false});
  }
  for (std::size_t i = 0; i < regs.map.values.size(); ++i) {
    layout.values.push_back(
        {plan.values[i], regs.map.values[i].address, regs.map.values[i].function_code == 4});
  }
  layout.heartbeat_address = *regs.map.heartbeat_address;
  hal::modbus::Codec echo;
  echo.type = hal::modbus::RegisterType::uint16;
  layout.heartbeat_echo = {echo, regs.heartbeat_echo_address,
                           regs.heartbeat_echo_function_code == 4};
  layout.control_address = regs.control_address;
  layout.command_address = regs.command_address;
  layout.closed_loop = loop;
  layout.holding = extent_of(holding);
  layout.input = extent_of(input);
  return layout;
}

}  // namespace excite::sim::server
