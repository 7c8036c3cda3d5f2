// SPDX-License-Identifier: MIT
#pragma once
// From excite-plant's controller file (plant.controller, --controller) to the controller in
// its loop: the file read and its controller made by sim/control (the file's own checks,
// a DMC not integrally controllable for this plant refused), then checked against the
// plant it will run on.

#include <memory>
#include <string>

#include "sim/plants/plant.hpp"
#include "sim/server/closed_loop.hpp"

namespace excite::sim::server {

/// The controller of `path` in the loop of `plant` stepped every `sample_time_min` minutes.
/// Refused by name (config::Error, "FILE: FIELD = VALUE, expected WHAT"): the file's own
/// errors; a sample time other than the plant's; a model with other input or output counts
/// than the plant's. The applied MV's box is the file's [[mv]] min and max (none: unbounded).
std::unique_ptr<ClosedLoop> load_closed_loop(const std::string& path, const Plant& plant,
                                             double sample_time_min);

}  // namespace excite::sim::server
