// SPDX-License-Identifier: MIT
// What the multisine tests share: the flat Schroeder set and the case study's gain.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "host/multisine/phases.hpp"
#include "host/multisine/synthesis.hpp"

namespace excite::host::multisine::testing {

// `count` lines at bins 1 … count, amplitude 1, Schroeder's phases for a flat spectrum.
inline std::vector<Line> flat_schroeder(std::uint32_t count) {
  const auto phases = schroeder_phases_equal(count);
  std::vector<Line> lines(count);
  for (std::uint32_t k = 0; k < count; ++k) lines[k] = {k + 1, 1.0, phases[k]};
  return lines;
}

// G(0) of the 4×4 column/side-stripper (6.3.1): σ = 20.470, 10.141, 5.046, 0.1635.
inline Eigen::MatrixXd case_study_gain() {
  Eigen::MatrixXd g(4, 4);
  g << 4.09, 6.36, -0.25, -0.49,  //
      -4.17, 6.93, -0.05, 1.53,   //
      1.73, 5.11, 4.61, -5.49,    //
      -11.2, 14.0, -0.1, 4.49;
  return g;
}

}  // namespace excite::host::multisine::testing
