// SPDX-License-Identifier: MIT
#include "sim/server/load_closed_loop.hpp"

#include "base/config/document.hpp"
#include "base/config/error.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"

namespace excite::sim::server {

std::unique_ptr<ClosedLoop> load_closed_loop(const std::string& path, const Plant& plant,
                                             double sample_time_min) {
  const control::ControllerFile file = control::load_controller_file(path);
  if (file.sample_time_min != sample_time_min) {
    throw config::Error(file.source, {}, "sample_time_min",
                        config::format_number(file.sample_time_min),
                        "the plant's sample time, " + config::format_number(sample_time_min) +
                            " min (the controller steps once per plant sample)");
  }
  const std::unique_ptr<Plant> model = control::load_model(file);
  if (model->inputs() != plant.inputs() || model->outputs() != plant.outputs()) {
    throw config::Error(file.source, {}, "model.plant",
                        "\"" + file.model.plant + "\" (" + std::to_string(model->inputs()) +
                            " inputs, " + std::to_string(model->outputs()) + " outputs)",
                        "a model of the served plant's size, " + std::to_string(plant.inputs()) +
                            " inputs and " + std::to_string(plant.outputs()) + " outputs (" +
                            plant.name() + ")");
  }
  const Eigen::MatrixXd gain = plant.static_gain();
  std::unique_ptr<control::Controller> controller = control::make_controller(file, *model, &gain);
  std::vector<double> min;
  std::vector<double> max;
  for (int i = 0; i < controller->inputs(); ++i) {
    const auto at = static_cast<std::size_t>(i);
    const bool given = at < file.dmc.mv.size();
    min.push_back(given ? file.dmc.mv[at].min : -control::kUnlimited);
    max.push_back(given ? file.dmc.mv[at].max : control::kUnlimited);
  }
  return std::make_unique<ClosedLoop>(std::move(controller), std::move(min), std::move(max));
}

}  // namespace excite::sim::server
