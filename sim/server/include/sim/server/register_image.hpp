// SPDX-License-Identifier: MIT
#pragma once
// The plant's register image: the libmodbus mapping (holding and input tables sized to the
// layout) and the conversions between it and the plant, with hal's codecs — setpoints are
// decoded exactly as hal's ModbusFieldBus encodes them, values encoded as it decodes them.

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/server/server_layout.hpp"

struct _modbus_mapping_t;

namespace excite::sim::server {

class RegisterImage {
 public:
  /// Allocates the tables; setpoints start at `input_baseline` (the plant holds its
  /// operating point until the gateway writes), values at `output_baseline`.
  RegisterImage(ServerLayout layout, const std::vector<double>& input_baseline,
                const std::vector<double>& output_baseline);
  ~RegisterImage();
  RegisterImage(const RegisterImage&) = delete;
  RegisterImage& operator=(const RegisterImage&) = delete;

  const ServerLayout& layout() const { return layout_; }
  _modbus_mapping_t* mapping() { return mapping_; }

  /// Records that a write request covered holding registers [address, address + count):
  /// each setpoint it touches is from now on read from its registers.
  void note_write(std::uint32_t address, std::uint32_t count);

  /// The setpoints, engineering units, one per plant input: the input baseline exactly
  /// until the gateway first writes a setpoint, then its decoded registers. A float32
  /// register pair that is not finite keeps the last good value and is counted.
  void read_setpoints(double* u);
  /// Writes the process values (one per plant output). An int16/uint16 value outside its
  /// engineering range cannot be encoded: the register holds the range's end (as a
  /// transmitter saturates) and the value is counted per output (`misfits`) — never silently.
  void write_values(const double* y);

  /// Rewrites every setpoint register with the input baseline (the watchdog's safe state):
  /// the next sample and every reader see the baseline.
  void restore_setpoint_baseline();
  /// The raw setpoint registers, setpoint by setpoint in plant-input order, and back.
  std::vector<std::uint16_t> setpoint_registers() const;
  void set_setpoint_registers(const std::vector<std::uint16_t>& registers);

  /// A setpoint a write would give a value outside [min, max] (or not finite).
  struct OutOfLimits {
    std::size_t input = 0;
    double value = 0.0;
  };
  /// Checks a write of `count` registers at `address` (`data`: their big-endian bytes, as in
  /// the request) before it is applied: every setpoint it touches is decoded from the
  /// written registers, the others of a float32 pair from the image. Limits per input,
  /// absolute; a float32 setpoint is allowed its register's rounding (relative 2^-23).
  std::optional<OutOfLimits> check_write(std::uint32_t address, std::uint32_t count,
                                         const std::uint8_t* data, const std::vector<double>& min,
                                         const std::vector<double>& max) const;
  /// The same for the test offsets under a controller (README "Closed loop", offset limits):
  /// `limit` per offset register, MV offsets then CV setpoint offsets; OutOfLimits::input is
  /// that offset's index. A value beyond ±limit (or not finite) is out.
  std::optional<OutOfLimits> check_offset_write(std::uint32_t address, std::uint32_t count,
                                                const std::uint8_t* data,
                                                const std::vector<double>& limit) const;

  /// The registers the watchdog guards: the setpoints in the open loop, the test offsets
  /// under a controller (README, "Closed loop"); and their safe state (the input baseline,
  /// every offset zero). The watchdog sets what is written while tripped aside with these.
  std::vector<std::uint16_t> guarded_registers() const;
  void set_guarded_registers(const std::vector<std::uint16_t>& registers);
  void restore_guarded();

  // Closed loop only (layout().closed_loop):
  /// Whether a write of [address, address + count) touches a setpoint register (under a
  /// controller the controller owns the MVs: such a write is refused).
  bool touches_setpoints(std::uint32_t address, std::uint32_t count) const;
  /// The MV test offsets (one per input) and CV setpoint offsets (one per output) as
  /// written; a value that is not finite keeps the last good one and is counted
  /// (rejected_setpoints). No allocation.
  void read_offsets(double* mv_offsets, double* sp_offsets);
  /// The operator's controller switch register (raw).
  std::uint16_t controller_switch() const;
  /// Writes the controller's read block: moves, applied MVs (deviations), setpoints in
  /// force, statuses and mode; and the applied MVs, absolute (`u`), into the setpoint
  /// registers, so a reader of `<name>_sp` sees what the plant got. No allocation.
  void write_controller(const double* moves, const double* applied, const double* setpoints,
                        const std::uint16_t* status, std::uint16_t mode, const double* u);

  std::uint16_t heartbeat() const;
  std::uint16_t heartbeat_echo() const;
  void set_heartbeat_echo(std::uint16_t value);

  /// Control block register `index` (0..control_block_size−1); only with a control block.
  std::uint16_t control(std::uint32_t index) const;
  void set_control(std::uint32_t index, std::uint16_t value);

  /// Raw access by protocol address (for tests and the request checks); the address must
  /// lie in the table's extent.
  std::uint16_t holding(std::uint32_t address) const;
  void set_holding(std::uint32_t address, std::uint16_t value);
  std::uint16_t input(std::uint32_t address) const;

  bool in_holding(std::uint32_t address) const;

  std::uint64_t rejected_setpoints() const { return rejected_setpoints_; }
  std::uint64_t clamped_values() const { return clamped_values_; }

  /// Values of one output that did not fit its register (int16/uint16 outside
  /// [eng_min, eng_max]): how many samples, and the lowest and highest such value.
  struct Misfit {
    std::uint64_t count = 0;
    double lowest = 0.0;
    double highest = 0.0;
  };
  /// One per plant output, in plant order.
  const std::vector<Misfit>& misfits() const { return misfits_; }

 private:
  std::uint16_t* cell(const PlacedValue& value) const;
  // `p`'s value once a write of `count` registers at `address` (`data`, big-endian bytes) is
  // applied; nullopt when the write does not touch it.
  std::optional<double> value_after_write(const PlacedValue& p, std::uint32_t address,
                                          std::uint32_t count, const std::uint8_t* data) const;
  void encode(const PlacedValue& value, double x);
  double decode(const PlacedValue& value) const;

  ServerLayout layout_;
  _modbus_mapping_t* mapping_ = nullptr;
  std::vector<double> input_baseline_;
  std::vector<double> last_setpoints_;
  std::vector<bool> written_;
  std::vector<double> last_offsets_;  // closed loop: MV then CV offsets, last good values
  std::uint64_t rejected_setpoints_ = 0;
  std::uint64_t clamped_values_ = 0;
  std::vector<Misfit> misfits_;
};

}  // namespace excite::sim::server
