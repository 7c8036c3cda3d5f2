// SPDX-License-Identifier: MIT
#pragma once
// What excite-plant's command line sets over its configuration file (README, "Running"),
// applied here, in the configuration room, rather than merged by hand in main(): the
// plant, its noise and sample time, the watchdog, the input limits, and the pacing (plant
// time to wall-clock time through std::chrono). Every error is a config::Error naming the
// option or the file's field, the value and what was expected.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/server/plant_process.hpp"
#include "sim/server/plant_server.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {

/// The sample time's unit, minutes; std::chrono converts it to wall-clock seconds.
using Minutes = std::chrono::duration<double, std::ratio<60>>;

/// The command line's settings over the file's; an empty field leaves the file's.
struct ServerOverrides {
  std::string plant;                        // --plant: a library plant, or a plant file NAME.toml
  std::string plant_file;                   // --plant-file (older form)
  std::optional<double> noise_variance;     // --noise-var, on every output
  std::optional<std::uint64_t> noise_seed;  // --seed
  std::optional<double> sample_time_min;    // --sample-time-min
  std::optional<double> watchdog_s;         // --watchdog-s
  std::optional<double> input_range;        // --input-range: baseline ± R on every input
  // Pacing when free-running: --speedup (plant minutes per wall minute) or the older
  // --sample-time-s (wall-clock seconds per sample); neither: real time.
  std::optional<double> speedup;
  std::optional<double> sample_time_s;
  // --plan: the plan the gateway will stream. Its sample time must be the plant's: a plant
  // stepped at another T than the plan's rows would answer another experiment.
  std::string plan;
  std::string controller;  // --controller: the controller file (overrides plant.controller)
};

/// The plant, its noise and its sample time from `overrides` into `config` (read from
/// `source`); the sample time's seconds must lie within the gateway's tick periods
/// (firmware/app/timing_range.hpp). With a plan, refuses a plan that cannot be read and
/// one whose sample time is not the plant's ("x.plan: sample_time_min = 0.5, expected the
/// plant's sample time, 1 min (plant.toml: plant.sample_time_min)").
void apply_overrides(ServerConfig& config, const ServerOverrides& overrides,
                     std::string_view source);

/// The wall-clock time per plant sample when free-running: 60 · T / speedup, the older
/// --sample-time-s, or T itself; within the gateway's tick periods.
std::chrono::duration<double> sample_period(Minutes sample_time, const ServerOverrides& overrides);

/// What the server needs besides the register image, from the configuration and the
/// command line: the watchdog, the input limits (checked around the process's baseline),
/// the pacing, and the run log's description of the plant. Refuses noise whose standard
/// deviation exceeds what an output's register carries (it would only clip). Returns a
/// warning ("" when none): a free-running watchdog shorter than one sample.
std::string complete_serve_options(ServeOptions& options, const ServerConfig& config,
                                   const ServerOverrides& overrides, const PlantProcess& process,
                                   const ServerLayout& layout, std::string_view source);

}  // namespace excite::sim::server
