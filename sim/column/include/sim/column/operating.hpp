// SPDX-License-Identifier: MIT
#pragma once
// The operating point of a column: the two manipulated inputs and the two feed
// disturbances (SPEC §7). Flows in kmol/min, compositions as mole fractions of the
// light component.

#include <string>

namespace excite::sim::column {

struct Operating {
  double reflux_kmol_min = 0.0;  ///< L, reflux to the top tray.
  double boilup_kmol_min =
      0.0;                     ///< V, boil-up (vapour from the reboiler, or its steam equivalent).
  double feed_kmol_min = 0.0;  ///< F, feed rate.
  double feed_light = 0.0;     ///< z_F, light-component mole fraction of the feed.
};

/// Throws std::invalid_argument naming the field, its value and what was expected when a
/// flow is not finite or negative, or z_F is outside [0, 1]. `context` prefixes the message.
void validate(const Operating& op, const std::string& context);

}  // namespace excite::sim::column
