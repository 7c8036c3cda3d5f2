// SPDX-License-Identifier: MIT
#include "sim/server/server_overrides.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>

#include "base/config/document.hpp"
#include "base/config/error.hpp"
#include "firmware/app/timing_range.hpp"
#include "firmware/plan/codec.hpp"

namespace excite::sim::server {
namespace {

[[noreturn]] void bad(const std::string& field, const std::string& value,
                      const std::string& expected) {
  throw config::Error(field, value, expected);
}

// The wall-clock seconds per plant sample, and the sample time as seconds, within the
// gateway's tick periods (firmware/app/timing_range.hpp: the same numbers, not a copy).
void check_period(const std::string& option, const std::string& value,
                  std::chrono::duration<double> period, const std::string& what) {
  const double seconds = period.count();
  if (!(seconds >= app::kMinPeriodS && seconds <= app::kMaxPeriodS)) {
    bad(option, value,
        what + " within the gateway's tick periods, " + config::format_number(app::kMinPeriodS) +
            " … " + config::format_number(app::kMaxPeriodS) + " s (got " +
            config::format_number(seconds) + " s)");
  }
}

// The plan the gateway will stream, against the plant's sample time T (minutes; `where`
// names the setting T came from). Equal to a part in 1e9: the plan stores T as a double,
// plant.toml as the shortest text that reads back exactly.
void check_plan(const std::string& path, double sample_time_min, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  if (!in) bad("--plan", "\"" + path + "\"", "a plan file that can be opened");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  auto plan = std::make_unique<plan::Plan>();  // large: not on the stack
  if (const Status s = plan::decode(bytes, *plan); !s) {
    bad("--plan", "\"" + path + "\"", std::string("a plan file (") + s.message() + ")");
  }
  const double t = plan->meta.sample_time_min;
  if (!(std::abs(t - sample_time_min) <= 1e-9 * sample_time_min)) {
    throw config::Error(path, {}, "sample_time_min", config::format_number(t),
                        "the plant's sample time, " + config::format_number(sample_time_min) +
                            " min (" + where + "): the plant steps once per row of the plan");
  }
}

// The input limits: baseline ± R from the command line, or the file's, around the baseline.
void input_limits(ServeOptions& options, const PlantSettings& plant,
                  const ServerOverrides& overrides, const std::vector<double>& u0,
                  std::string_view source) {
  if (overrides.input_range) {
    for (const double b : u0) {
      options.input_min.push_back(b - *overrides.input_range);
      options.input_max.push_back(b + *overrides.input_range);
    }
    return;
  }
  if (plant.input_min.empty()) return;
  const std::string src(source);
  const std::size_t n = u0.size();
  if (plant.input_min.size() != n) {
    bad(src + ": plant.input_min", std::to_string(plant.input_min.size()) + " values",
        std::to_string(n) + " (one per plant input)");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(plant.input_min[i] <= u0[i] && u0[i] <= plant.input_max[i])) {
      bad(src + ": plant.input_min/input_max[" + std::to_string(i) + "]",
          "[" + config::format_number(plant.input_min[i]) + ", " +
              config::format_number(plant.input_max[i]) + "]",
          "limits around the input baseline " + config::format_number(u0[i]));
    }
  }
  options.input_min = plant.input_min;
  options.input_max = plant.input_max;
}

// The offset limits (under a controller only): one per offset register, n + m.
void offset_limits(ServeOptions& options, const PlantSettings& plant, std::size_t n, std::size_t m,
                   std::string_view source) {
  if (plant.offset_limit.empty()) return;
  const std::string src(source);
  if (plant.controller.empty()) {
    bad(src + ": plant.offset_limit", std::to_string(plant.offset_limit.size()) + " values",
        "no offset limits without a controller (plant.controller or --controller)");
  }
  if (plant.offset_limit.size() != n + m) {
    bad(src + ": plant.offset_limit", std::to_string(plant.offset_limit.size()) + " values",
        std::to_string(n + m) + " (one per MV offset, then one per CV setpoint offset)");
  }
  options.offset_limit = plant.offset_limit;
}

// Noise whose standard deviation exceeds what an output's register carries (float32:
// ±FLT_MAX; a scaled int16/uint16: its engineering range) only clips: refused.
void check_noise_fits(const PlantSettings& plant, const ServerOverrides& overrides,
                      const ServerLayout& layout, const std::vector<std::string>& output_names,
                      std::string_view source) {
  const std::vector<double>& v = plant.noise_variance;
  if (v.empty()) return;
  for (std::size_t j = 0; j < layout.values.size(); ++j) {
    const hal::modbus::Codec& c = layout.values[j].codec;
    const double span = c.type == hal::modbus::RegisterType::float32
                            ? 2.0 * static_cast<double>(std::numeric_limits<float>::max())
                            : c.eng_max - c.eng_min;
    const double variance = v.size() == 1 ? v.front() : v[std::min(j, v.size() - 1)];
    if (!(std::sqrt(variance) <= span)) {
      bad(overrides.noise_variance ? "--noise-var" : std::string(source) + ": plant.noise_variance",
          config::format_number(variance),
          "a variance whose standard deviation fits output " + output_names[j] +
              "'s register (at most " + config::format_number(span) + ", the range it carries)");
    }
  }
}

}  // namespace

void apply_overrides(ServerConfig& config, const ServerOverrides& o, std::string_view source) {
  PlantSettings& plant = config.plant;
  if (!o.plant.empty()) {
    const bool file = o.plant.size() > 5 && o.plant.ends_with(".toml");
    plant.library = file ? "" : o.plant;
    plant.file = file ? std::filesystem::absolute(o.plant).string() : "";
  }
  if (!o.plant_file.empty()) {
    plant.file = std::filesystem::absolute(o.plant_file).string();
    plant.library.clear();
  }
  if (!o.controller.empty()) plant.controller = std::filesystem::absolute(o.controller).string();
  if (!plant.controller.empty() && std::filesystem::path(plant.controller).is_relative()) {
    plant.controller = (config.base_directory / plant.controller).string();
  }
  if (o.noise_variance) plant.noise_variance = {*o.noise_variance};
  if (o.noise_seed) plant.noise_seed = *o.noise_seed;
  if (o.sample_time_min) plant.sample_time_min = *o.sample_time_min;
  const std::string where =
      o.sample_time_min ? "--sample-time-min" : std::string(source) + ": plant.sample_time_min";
  check_period(where, config::format_number(plant.sample_time_min), Minutes(plant.sample_time_min),
               "minutes whose seconds lie");
  if (!o.plan.empty()) check_plan(o.plan, plant.sample_time_min, where);
}

std::chrono::duration<double> sample_period(Minutes sample_time, const ServerOverrides& o) {
  if (o.speedup) {
    const std::chrono::duration<double> period = sample_time / *o.speedup;
    check_period("--speedup", config::format_number(*o.speedup), period,
                 "a factor whose wall-clock seconds per sample (60 · T / X, T = " +
                     config::format_number(sample_time.count()) + " min) lie");
    return period;
  }
  if (o.sample_time_s) {
    const std::chrono::duration<double> period(*o.sample_time_s);
    check_period("--sample-time-s", config::format_number(*o.sample_time_s), period, "seconds");
    return period;
  }
  return sample_time;
}

std::string complete_serve_options(ServeOptions& options, const ServerConfig& config,
                                   const ServerOverrides& overrides, const PlantProcess& process,
                                   const ServerLayout& layout, std::string_view source) {
  const Plant& plant = process.plant();
  options.watchdog_s = overrides.watchdog_s.value_or(config.plant.watchdog_s);
  input_limits(options, config.plant, overrides, process.input_baseline(), source);
  offset_limits(options, config.plant, static_cast<std::size_t>(plant.inputs()),
                static_cast<std::size_t>(plant.outputs()), source);
  options.sample_period = sample_period(Minutes(process.sample_time_min()), overrides);
  check_noise_fits(config.plant, overrides, layout, plant.output_names(), source);
  options.plant_description = plant.name() + " (excite-plant)";
  options.time_scales.tau_high_min = config.plant.tau_high_min;
  options.time_scales.beta = config.plant.beta;
  options.input_names = plant.input_names();
  options.output_names = plant.output_names();
  options.input_units = plant.input_units();
  options.output_units = plant.output_units();
  // A free-running watchdog shorter than one sample trips between the gateway's writes:
  // the inputs sit at the baseline part of every sample while the gateway logs the
  // excitation (issue 28 item 3). Warned, and the trips are counted at the stop.
  const double period_s = options.sample_period.count();
  if (options.lockstep || options.watchdog_s <= 0.0 || options.watchdog_s >= period_s) return "";
  return "watchdog " + config::format_number(options.watchdog_s) +
         " s is shorter than one sample period (" + config::format_number(period_s) +
         " s): it trips between the gateway's writes and holds the inputs at the baseline; give "
         "it at least two periods";
}

}  // namespace excite::sim::server
