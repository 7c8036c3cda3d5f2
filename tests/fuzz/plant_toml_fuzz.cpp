// SPDX-License-Identifier: MIT
// Fuzzes plant files (sim/lti, plant_from_toml: a transfer-function matrix in TOML with the
// element grammar), then builds the discrete plant at T = 1 min and steps it 16 samples with
// every input at 1. Contracts checked: errors are std::invalid_argument (any other exception
// escapes and is reported as a crash); a parsed plant has at least one input and output and
// one name per channel; the discrete plant's outputs stay finite when every pole is stable.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "check.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/plant_toml.hpp"

namespace {

bool every_pole_stable(const excite::sim::TransferMatrix& g) {
  for (int out = 0; out < g.outputs(); ++out) {
    for (int in = 0; in < g.inputs(); ++in) {
      for (const auto& term : g.element(out, in).terms()) {
        for (const auto& pole : term.pole_locations()) {
          if (!(pole.real() < 0.0)) return false;
        }
      }
    }
  }
  return true;
}

void step_plant(const excite::sim::TransferMatrix& g) {
  constexpr double sample_time_min = 1.0;
  constexpr int samples = 16;
  excite::sim::DiscretePlant plant(g, sample_time_min);
  const bool stable = every_pole_stable(g);
  std::vector<double> u(static_cast<std::size_t>(plant.inputs()), 1.0);
  std::vector<double> y(static_cast<std::size_t>(plant.outputs()), 0.0);
  for (int k = 0; k < samples; ++k) {
    plant.step(u.data(), y.data());
    if (!stable) continue;
    for (const double v : y) EXCITE_FUZZ_CHECK(std::isfinite(v), "stable plant, output not finite");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const excite::sim::PlantDefinition plant = excite::sim::plant_from_toml(text, "fuzz.toml");
    const excite::sim::TransferMatrix& g = plant.g;
    EXCITE_FUZZ_CHECK(g.inputs() >= 1 && g.outputs() >= 1, "a plant has inputs and outputs");
    EXCITE_FUZZ_CHECK(g.input_names().size() == static_cast<std::size_t>(g.inputs()) &&
                          g.output_names().size() == static_cast<std::size_t>(g.outputs()),
                      "one name per channel");
    step_plant(g);
  } catch (const std::invalid_argument& e) {
    EXCITE_FUZZ_CHECK(std::string_view(e.what()).size() > 0, "an error names its reason");
  }
  return 0;
}
