// SPDX-License-Identifier: MIT
#pragma once
// An identified model as a simulated plant (`excite simulate --plant MODEL.json`), so a model
// can be run against any plan exactly like the plant it stands for.

#include <memory>

#include "host/export/formats.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// sim/lti's transfer-function matrix of the model's elements (to_term, element.hpp), with
/// the model's input and output names, as a linear sim::Plant named `m.source`. Time
/// constants below kVanishingTimeConstant of the model's sample time are taken as 0 (as
/// identification simulates them, host/identify/element.hpp). Throws std::invalid_argument
/// for an element without parameters (require_every_element) or repeated names.
std::unique_ptr<sim::Plant> plant_from_model(const NamedModel& m);

}  // namespace excite::host
