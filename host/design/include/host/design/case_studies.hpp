// SPDX-License-Identifier: MIT
#pragma once
// The prior knowledge of each library plant's case study (SPEC §4, §7), so that presets
// work without a spec file: `excite design --plant alatiqi4x4 --preset prbsUnc`.

#include <string>
#include <string_view>
#include <vector>

#include "host/design/prior_knowledge.hpp"

namespace excite::host {

/// Names of the plants that have a case study (the library plants).
std::vector<std::string> case_study_plants();

/// G(0) of a simulated plant (sim::make_plant: a library plant, colaA, pilot15 or a plant
/// file; std::invalid_argument listing the known plants otherwise).
Eigen::MatrixXd plant_gain(std::string_view plant);

/// Measurement-noise variance of the case study on every output: 5e-4 for the linear
/// plants (the thesis's s² = 0.03 is a noise power; over its 60 s sample time it is the
/// variance 0.03/60, SPEC §4), 1e-8 for the columns, whose outputs are mole fractions.
double case_study_noise_variance(std::string_view plant);

/// Prior knowledge of `plant`, its gain G(0) from the plant library.
/// std::invalid_argument listing the known plants otherwise.
PriorKnowledge case_study(std::string_view plant);

}  // namespace excite::host
