// SPDX-License-Identifier: MIT
#include "host/design/sizing.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace excite::host {
namespace {

// The thesis's factors c (Ahmed's case study, chapter 6; collected in issue 14 from its
// figures and tables). They are values the thesis chose, not results of a rule: keep them
// here, in one place. Peak for steps and PRBS, RMS_j·‖G(0) e_j‖ for multisines.
// msGlmZipm has no published factor: ours follows design 8 relative to design 4 (the
// uncorrelated part at 0.7 of the simultaneous plain design, 0.35 along v_n), applied to
// the simultaneous Guillaume design's 0.91.
const std::vector<DesignSize>& table() {
  static const std::vector<DesignSize> all = {
      {"stepSeq", SizeMeasure::peak, 1.2, 0.0, true},
      {"stepDir", SizeMeasure::peak, 0.5, 0.0, true},
      {"prbsSeq", SizeMeasure::peak, 1.8, 0.0, true},
      {"prbsUnc", SizeMeasure::peak, 1.0, 0.0, true},
      {"prbsSeqDir", SizeMeasure::peak, 0.5, 0.0, true},
      {"prbsSimDir", SizeMeasure::peak, 0.4, 0.0, true},
      {"prbsDirCorrSeq", SizeMeasure::peak, 0.5, 1.0, true},
      {"prbsDirCorrSim", SizeMeasure::peak, 0.35, 0.7, true},
      {"msSrdSeq", SizeMeasure::rms, 1.28, 0.0, true},
      {"msSrdSeqDir", SizeMeasure::rms, 1.28, 0.0, true},
      {"msGlmSeq", SizeMeasure::rms, 0.875, 0.0, true},
      {"msGlmSeqDir", SizeMeasure::rms, 0.875, 0.0, true},
      {"msSrdSim", SizeMeasure::rms, 1.42, 0.0, true},
      {"msSrdSimDir", SizeMeasure::rms, 1.42, 0.0, true},
      {"msGlmSim", SizeMeasure::rms, 0.91, 0.0, true},
      {"msGlmSimDir", SizeMeasure::rms, 0.91, 0.0, true},
      {"msGlmZipm", SizeMeasure::rms, 0.35 * 0.91, 0.7 * 0.91, false},
  };
  return all;
}

}  // namespace

const DesignSize& design_size(std::string_view acronym) {
  for (const DesignSize& s : table()) {
    if (s.acronym == acronym) return s;
  }
  throw std::invalid_argument("preset = \"" + std::string(acronym) +
                              "\": no static-output size (host/design/sizing.cpp)");
}

}  // namespace excite::host
