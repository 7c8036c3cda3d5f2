// SPDX-License-Identifier: MIT
#include "host/design/prior_knowledge.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "base/config/document.hpp"
#include "firmware/signal/recipe.hpp"

namespace excite::host {
namespace {

[[noreturn]] void fail(const std::string& field, double value, const std::string& expected) {
  std::ostringstream msg;
  msg << field << " = " << value << ", expected " << expected;
  throw std::invalid_argument(msg.str());
}

void require_positive(const std::string& field, double value) {
  if (!(std::isfinite(value) && value > 0.0)) fail(field, value, "a positive number");
}

}  // namespace

void validate(const PriorKnowledge& prior) {
  validate_inputs(prior);
  require_positive("tau_low_min", prior.tau_low_min);
  require_positive("tau_high_min", prior.tau_high_min);
  if (prior.tau_low_min > prior.tau_high_min) {
    fail("tau_low_min", prior.tau_low_min,
         "at most tau_high_min = " + config::format_number(prior.tau_high_min));
  }
  require_positive("alpha", prior.alpha);
  require_positive("beta", prior.beta);
  if (!(std::isfinite(prior.step_length_min) && prior.step_length_min >= 0.0)) {
    fail("step_length_min", prior.step_length_min, "0 (derived) or a positive number");
  }
}

void validate_inputs(const PriorKnowledge& prior) {
  require_positive("sample_time_min", prior.sample_time_min);
  const auto n = prior.inputs.size();
  if (n < 1 || n > signal::kMaxChannels) {
    fail("inputs (count)", static_cast<double>(n),
         "1…" + std::to_string(signal::kMaxChannels) + " inputs");
  }
  for (std::size_t j = 0; j < n; ++j) {
    const InputSpec& in = prior.inputs[j];
    const std::string field = "inputs[" + std::to_string(j) + "]";
    if (!(std::isfinite(in.min) && in.min < 0.0)) fail(field + ".min", in.min, "a negative number");
    if (!(std::isfinite(in.max) && in.max > 0.0)) fail(field + ".max", in.max, "a positive number");
    const double room = std::min(-in.min, in.max);
    if (!(std::isfinite(in.amplitude) && in.amplitude > 0.0 && in.amplitude <= room)) {
      fail(field + ".amplitude", in.amplitude,
           "in (0, " + config::format_number(room) + "], inside the input limits");
    }
  }
  if (prior.gain.size() != 0) {
    if (prior.gain.cols() != static_cast<Eigen::Index>(n)) {
      fail("gain (columns)", static_cast<double>(prior.gain.cols()),
           std::to_string(n) + " columns, one per input");
    }
    for (Eigen::Index r = 0; r < prior.gain.rows(); ++r) {
      for (Eigen::Index c = 0; c < prior.gain.cols(); ++c) {
        if (!std::isfinite(prior.gain(r, c))) {
          fail("gain[" + std::to_string(r) + "][" + std::to_string(c) + "]", prior.gain(r, c),
               "a finite number");
        }
      }
    }
  }
}

}  // namespace excite::host
