// SPDX-License-Identifier: MIT
#pragma once
// From a controller file to a running controller: its model loaded, the model's step
// responses taken, the file's settings checked against the model's sizes, and a DMC whose
// model is not integrally controllable for the plant refused.

#include <Eigen/Dense>

#include <memory>

#include "sim/control/controller.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::control {

/// The model the file names (`model.plant`: a library plant or a plant file, through
/// sim::make_plant). A `model.model_file` (a model of `excite identify`, JSON) is refused
/// by name: excite reads it (host/export's plant_from_model) and passes the plant to
/// make_controller itself. Throws config::Error prefixed with the file's source.
std::unique_ptr<Plant> load_model(const ControllerFile& file);

/// The controller of `file` on `model`. With `plant_gain` (the G(0) of the plant the
/// controller will run on, e.g. the true plant of a simulation) a DMC whose model has a
/// principal minor of the other sign is refused, saying it is not integrally controllable;
/// a PI loop whose Kc has the other sign than the model's paired gain is refused too.
/// Throws config::Error prefixed with the file's source.
std::unique_ptr<Controller> make_controller(const ControllerFile& file, Plant& model,
                                            const Eigen::MatrixXd* plant_gain = nullptr);

}  // namespace excite::sim::control
