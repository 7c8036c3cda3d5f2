// SPDX-License-Identifier: MIT
#include "host/export/model_plant.hpp"

#include "host/identify/element.hpp"

namespace excite::host {

std::unique_ptr<sim::Plant> plant_from_model(const NamedModel& m) {
  require_every_element(m);
  const std::size_t p = m.outputs.size(), n = m.inputs.size();
  // A zero matrix with the model's names; then every element exactly, not through text.
  sim::TransferMatrix g = sim::TransferMatrix::parse(
      std::vector<std::vector<std::string>>(p, std::vector<std::string>(n, "0")), m.inputs,
      m.outputs);
  for (int o = 0; o < m.model.outputs; ++o) {
    for (int i = 0; i < m.model.inputs; ++i) {
      const ElementModel& e = m.model.element(o, i).value;
      g.set_element(o, i, sim::Element({to_term(e, m.model.sample_time_min)}, ""));
    }
  }
  return sim::make_linear_plant(m.source, std::move(g));
}

}  // namespace excite::host
