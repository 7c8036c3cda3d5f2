// SPDX-License-Identifier: MIT
#include "sim/control/controller.hpp"

namespace excite::sim::control {

const char* to_string(StepStatus s) noexcept {
  switch (s) {
    case StepStatus::ok:
      return "ok";
    case StepStatus::held:
      return "held";
    case StepStatus::qp_fallback:
      return "qp_fallback";
  }
  return "?";
}

const char* to_string(MvStatus s) noexcept {
  switch (s) {
    case MvStatus::ok:
      return "ok";
    case MvStatus::clamped_low:
      return "clamped_low";
    case MvStatus::clamped_high:
      return "clamped_high";
    case MvStatus::move_limited:
      return "move_limited";
  }
  return "?";
}

}  // namespace excite::sim::control
