// SPDX-License-Identifier: MIT
#include "sim/column/operating.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace excite::sim::column {
namespace {

void require_flow(double value, const char* field, const std::string& context) {
  if (std::isfinite(value) && value >= 0.0) return;
  std::ostringstream msg;
  msg << context << ": " << field << " = " << value
      << " kmol/min, expected a finite, non-negative flow";
  throw std::invalid_argument(msg.str());
}

}  // namespace

void validate(const Operating& op, const std::string& context) {
  require_flow(op.reflux_kmol_min, "reflux L", context);
  require_flow(op.boilup_kmol_min, "boil-up V", context);
  require_flow(op.feed_kmol_min, "feed rate F", context);
  if (!(std::isfinite(op.feed_light) && op.feed_light >= 0.0 && op.feed_light <= 1.0)) {
    std::ostringstream msg;
    msg << context << ": feed composition z_F = " << op.feed_light
        << ", expected a mole fraction in [0, 1]";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace excite::sim::column
