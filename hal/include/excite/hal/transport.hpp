// SPDX-License-Identifier: MIT
#pragma once
// The transport seam (STYLE.md practice 8, "a transport owns its description"): what the
// gateway's configuration needs of a field-bus transport, without naming one. A transport
// (hal/modbus, hal/can) reads its own part of the configuration file — its [device] keys,
// its own sections, the mapping keys of each setpoint and value — knows what each channel's
// encoding can carry, describes its peer and its channels in words, and builds its
// hal::FieldBus. The table of transports by name is hal/transports (transports.hpp).
//
// Start-up code (allocates). The reading member functions throw config::Error in the one
// form "FIELD = VALUE, expected WHAT" (base/config), like every configuration reader;
// everything else returns.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"

namespace excite::config {
class Table;
}

namespace excite::hal {

/// Which list of the configuration a channel belongs to.
enum class ChannelKind : std::uint8_t { setpoint, value };

/// What one channel's field encoding can carry, in engineering units.
struct CarriedRange {
  bool bounded = false;  // false: float32, nothing to check
  double low = 0.0;      // engineering units at the low end of the encoding
  double high = 0.0;     // … and at the high end (low ≤ high)
  double count = 0.0;    // engineering units per raw count (> 0 when bounded)
  std::string what;      // "register 104 int16 raw 0..27648 = 0..2" / "CAN 0x210 int16 scale 0.1"
};

/// A configured bus and what the transport counts beside it.
struct MadeBus {
  std::unique_ptr<FieldBus> bus;  // configured (connected, nothing written); null on failure
  std::string error;              // "<field> = <value>, expected <what>" when !bus
  // The transport's own counts for the end-of-run summary ("" when it has none); set with
  // `bus`, valid while `bus` lives; called after the run (allocates).
  std::function<std::string()> counts_report;
};

/// One transport's part of the gateway configuration, read from the file and then used.
class TransportConfig {
 public:
  virtual ~TransportConfig() = default;

  /// The canonical name of [device] transport ("modbus-tcp", "can").
  [[nodiscard]] virtual std::string_view name() const noexcept = 0;

  // ---- reading the file (in this order; throw config::Error) ----

  /// The keys of [device] this transport reads (besides the gateway's own).
  [[nodiscard]] virtual std::vector<std::string> device_keys() const = 0;
  virtual void read_device(const config::Table& device) = 0;
  /// The root sections this transport owns (e.g. "map"); read_sections() reads them and
  /// refuses a section it cannot use; another transport's section is refused by the reader.
  [[nodiscard]] virtual std::vector<std::string> sections() const = 0;
  virtual void read_sections(const config::Table& root) = 0;
  /// The mapping keys a setpoint or value entry may carry (besides the gateway's own).
  [[nodiscard]] virtual std::vector<std::string> entry_keys() const = 0;
  /// Reads the mapping of the next entry of `kind` (entries come in file order).
  virtual void read_entry(const config::Table& entry, ChannelKind kind,
                          const std::string& name) = 0;
  /// After every entry: the whole mapping against the protocol.
  virtual void validate() const = 0;
  /// Verified writes: the value read back as setpoint `setpoint`'s baseline must decode the
  /// setpoint as it is written where both are the same field location (else each comparison
  /// would judge the encoding, not the field).
  virtual void check_readback(std::size_t setpoint, std::size_t value) const = 0;

  // ---- using it ----

  /// Builds and configures the bus. `clock` measures the age of received values where the
  /// transport needs it (must outlive the bus); `await_echo` (lock-step with a simulated
  /// peer): the value carrying the heartbeat echo, for a transport whose reads do not
  /// answer its writes by themselves.
  [[nodiscard]] virtual MadeBus make_bus(const Clock& clock,
                                         std::optional<std::size_t> await_echo) const = 0;
  /// One line naming the peer ("modbus-tcp 10.0.0.5:502 unit 1, response timeout 200 ms").
  [[nodiscard]] virtual std::string describe_peer() const = 0;
  /// One channel's location and encoding for messages ("register 100 float32 ABCD").
  [[nodiscard]] virtual std::string describe_channel(ChannelKind kind, std::size_t i) const = 0;
  /// The same in the dry run's fixed-width columns.
  [[nodiscard]] virtual std::string channel_columns(ChannelKind kind, std::size_t i) const = 0;
  /// The heartbeat's location in the dry run's columns; "" when none is configured.
  [[nodiscard]] virtual std::string heartbeat_columns() const = 0;
  /// Per channel of `kind`, in configuration order (empty when the mapping is invalid).
  [[nodiscard]] virtual std::vector<CarriedRange> carried_range(ChannelKind kind) const = 0;
  /// How long one exchange may take before it counts as failed, in seconds.
  [[nodiscard]] virtual double response_timeout_s() const = 0;
  /// "" when one tick's traffic fits a tick of `period_s` seconds, else why not.
  [[nodiscard]] virtual std::string check_tick(double period_s) const = 0;
};

}  // namespace excite::hal
