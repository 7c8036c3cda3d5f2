// SPDX-License-Identifier: MIT
#pragma once
// --limit CV=LOW:HIGH, repeated: CV test limits as deviations from each CV's baseline
// (excite scale, excite test, excite design); --mv-limit MV=LOW:HIGH the same for the MVs
// (excite design's setpoint excitation: the controller's MV limits).

#include <string>
#include <vector>

#include "host/adaptive/amplitude_control.hpp"

namespace excite::host {

/// The limits of every output named in `texts` (the others unlimited: ∓infinity). Throws
/// std::invalid_argument quoting the option for a malformed text, an unknown CV (listing
/// `outputs`, described as `whose` outputs, e.g. "the model's") or a non-finite number.
CvLimits parse_cv_limits(const std::vector<std::string>& texts,
                         const std::vector<std::string>& outputs, const std::string& whose);

/// The same for --mv-limit MV=LOW:HIGH over the inputs named `inputs` (the low and high
/// vectors then hold one entry per input).
CvLimits parse_mv_limits(const std::vector<std::string>& texts,
                         const std::vector<std::string>& inputs, const std::string& whose);

}  // namespace excite::host
