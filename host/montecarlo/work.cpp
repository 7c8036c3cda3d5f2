// SPDX-License-Identifier: MIT
#include "host/montecarlo/work.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "host/campaign/closed_loop_designs.hpp"
#include "host/design/presets.hpp"
#include "sim/library/library.hpp"
#include "sim/library/perturb.hpp"

namespace excite::host::montecarlo {
namespace {

bool parse_int(std::string_view text, int& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  Shard s;
  if (slash == std::string::npos || !parse_int(std::string_view(text).substr(0, slash), s.index) ||
      !parse_int(std::string_view(text).substr(slash + 1), s.count) || s.count < 1 ||
      s.count > 100000 || s.index < 1 || s.index > s.count) {
    throw std::invalid_argument("--shard = " + text + ", expected i/N with 1 <= i <= N <= 100000");
  }
  return s;
}

namespace {

// The closed loop's own options (work.hpp ClosedLoopConfig), each refused by its option's name.
void check_closed_loop(const Config& config) {
  const ClosedLoopConfig& c = config.closed_loop;
  check_excitation(c.excitation);
  check_directions(c.directions, c.excitation);
  check_switching(c.switching);
  if (c.prbs_phase > kMaxPrbsPhase)
    throw std::invalid_argument("--prbs-phase = " + std::to_string(c.prbs_phase) +
                                ", expected 0 to " + std::to_string(kMaxPrbsPhase));
  if (c.prbs_phase > 0 && c.excitation != "setpoint")
    throw std::invalid_argument("--prbs-phase = " + std::to_string(c.prbs_phase) +
                                " with --excitation " + c.excitation +
                                ", expected 0 (an MV dither is the open-loop preset as it is)");
  if (c.method != "two-stage" && c.method != "direct")
    throw std::invalid_argument("--method = " + c.method + ", expected two-stage or direct");
  (void)closed_loop_presets(config.designs);  // plain presets only
  if (!(c.limit_fraction > 0.0 && c.limit_fraction <= 1.0))
    throw std::invalid_argument("--limit-fraction = " + std::to_string(c.limit_fraction) +
                                ", expected 0 < fraction <= 1");
  if (!(c.mv_fraction >= 0.0 && c.mv_fraction <= 1.0))
    throw std::invalid_argument(
        "--mv-fraction = " + std::to_string(c.mv_fraction) +
        ", expected 0 <= fraction <= 1 (0: r sized by the CV limits alone)");
  if (!(c.model_perturb_percent >= 0.0 && c.model_perturb_percent < sim::kMaxPerturbPercent))
    throw std::invalid_argument(
        "--controller-perturb = " + sim::percent_text(c.model_perturb_percent) +
        ", expected a number of percent, 0 <= X < 100");
  if (!(std::isfinite(c.disturbance_std) && c.disturbance_std >= 0.0))
    throw std::invalid_argument("--disturbance-std = " + std::to_string(c.disturbance_std) +
                                ", expected a finite number >= 0");
  if (c.disturbance_std > 0.0 &&
      !(std::isfinite(c.disturbance_tau_min) && c.disturbance_tau_min > 0.0))
    throw std::invalid_argument("--disturbance-tau-min = " + std::to_string(c.disturbance_tau_min) +
                                ", expected a time constant > 0 min with --disturbance-std > 0");
}

}  // namespace

void normalise(Config& config) {
  const auto& table = presets();
  if (config.designs.empty()) {
    for (const PresetInfo& p : table) {
      if (!config.closed_loop.on() || !p.uses_directions()) config.designs.emplace_back(p.acronym);
    }
  } else {
    for (const std::string& name : config.designs) {
      if (std::none_of(table.begin(), table.end(),
                       [&](const PresetInfo& p) { return p.acronym == name; })) {
        std::string known;
        for (const PresetInfo& p : table)
          known += (known.empty() ? "" : ", ") + std::string(p.acronym);
        throw std::invalid_argument("--designs: " + name + ", expected one of " + known);
      }
      if (std::count(config.designs.begin(), config.designs.end(), name) > 1)
        throw std::invalid_argument("--designs: " + name + " given twice, expected each once");
    }
    std::vector<std::string> ordered;
    for (const PresetInfo& p : table) {
      if (std::find(config.designs.begin(), config.designs.end(), p.acronym) !=
          config.designs.end())
        ordered.emplace_back(p.acronym);
    }
    config.designs = ordered;
  }
  if (config.seeds < 1 || config.seeds > 1000000)
    throw std::invalid_argument("--seeds = " + std::to_string(config.seeds) +
                                ", expected 1 to 1000000");
  const std::uint64_t last_allowed =
      std::numeric_limits<std::uint64_t>::max() / kSeedStride - 1000000 - 1;
  if (config.first_seed > last_allowed)
    throw std::invalid_argument("--first-seed = " + std::to_string(config.first_seed) +
                                ", expected at most " + std::to_string(last_allowed));
  if (config.length_step_percent < 0 || config.length_step_percent > 100)
    throw std::invalid_argument("--length-step = " + std::to_string(config.length_step_percent) +
                                ", expected 0 to 100 (percent; 0: the whole run only)");
  if (!std::isfinite(config.noise_variance) || config.noise_variance < 0.0)
    throw std::invalid_argument("--noise-var = " + std::to_string(config.noise_variance) +
                                ", expected a finite number >= 0");
  sim::check_perturbable(config.plant, config.perturb_percent);
  if (config.closed_loop.on()) check_closed_loop(config);
}

std::vector<Unit> all_units(const Config& config) {
  std::vector<Unit> units;
  long long k = 0;
  for (std::size_t d = 0; d < config.designs.size(); ++d) {
    for (int s = 0; s < config.seeds; ++s) {
      units.push_back(
          {static_cast<int>(d), config.first_seed + static_cast<std::uint64_t>(s), k++});
    }
  }
  return units;
}

std::vector<Unit> shard_units(const Config& config) {
  std::vector<Unit> units;
  for (const Unit& u : all_units(config)) {
    if (u.number % config.shard.count == config.shard.index - 1) units.push_back(u);
  }
  return units;
}

std::vector<int> length_grid(const Config& config) {
  std::vector<int> grid;
  if (config.length_step_percent > 0) {
    for (int p = config.length_step_percent; p < 100; p += config.length_step_percent)
      grid.push_back(p);
  }
  grid.push_back(100);
  return grid;
}

}  // namespace excite::host::montecarlo
