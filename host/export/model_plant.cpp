// SPDX-License-Identifier: MIT
#include "host/export/model_plant.hpp"

#include "host/identify/element.hpp"
#include "sim/lti/sopdt.hpp"

namespace excite::host {

std::unique_ptr<sim::Plant> plant_from_model(const NamedModel& m) {
  require_every_element(m);
  const std::size_t p = m.outputs.size(), n = m.inputs.size();
  // A zero matrix with the model's names; then every element exactly, not through text.
  sim::TransferMatrix g = sim::TransferMatrix::parse(
      std::vector<std::vector<std::string>>(p, std::vector<std::string>(n, "0")), m.inputs,
      m.outputs);
  const double vanishing = kVanishingTimeConstant * m.model.sample_time_min;
  for (int o = 0; o < m.model.outputs; ++o) {
    for (int i = 0; i < m.model.inputs; ++i) {
      TwoPoleDelay e = m.model.element(o, i).value;
      if (e.tau1_min < vanishing) e.tau1_min = 0.0;
      if (e.tau2_min < vanishing) e.tau2_min = 0.0;
      g.set_element(o, i, sim::Element({sim::sopdt_term(e)}, ""));
    }
  }
  return sim::make_linear_plant(m.source, std::move(g));
}

}  // namespace excite::host
