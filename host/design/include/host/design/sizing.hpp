// SPDX-License-Identifier: MIT
#pragma once
// How big each design of Table 6.1 is (SPEC §3 "Sizing"): every design by the static
// output it causes, so that the experiments of a campaign are comparable.
//   plain designs:       input j moves by c / ‖G(0) e_j‖ (input j alone: static output norm c)
//   directional designs: u = c · σ_i⁻¹ v_i · s_i (direction i alone: static output norm c)
//   correlated designs:  uncorrelated part c_unc / ‖G(0) e_j‖ on input j, plus
//                        c · σ_n⁻¹ v_n · s along the weakest direction
// "Norm" is the peak of steps and PRBS and the RMS of multisines.

#include <string_view>

namespace excite::host {

enum class SizeMeasure { peak, rms };

struct DesignSize {
  std::string_view acronym;
  SizeMeasure measure;
  double c;           // plain: per input; directional: per direction; correlated: along v_n
  double unc;         // correlated designs only: the uncorrelated part's factor per input; else 0
  bool thesis_value;  // true: the thesis's factor; false: ours, by analogy (sizing.cpp)
};

/// The factor c of `acronym` (one of the 17 presets); std::invalid_argument otherwise.
const DesignSize& design_size(std::string_view acronym);

}  // namespace excite::host
