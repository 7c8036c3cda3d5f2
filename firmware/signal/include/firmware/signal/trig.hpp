// SPDX-License-Identifier: MIT
#pragma once
// Sine and cosine computed by the library itself from + − × / only, so table values do
// not depend on the target's libm (generate.hpp: bit-identical tables). Accuracy: a few
// units in the last place (about 1e-16 absolute).

#include <cstdint>

namespace excite::signal {

struct CosSin {
  double cos = 1.0;
  double sin = 0.0;
};

/// cos and sin of the angle 2π · m / period (exact integer reduction; 1 ≤ period < 2^61).
CosSin cos_sin_turn(std::uint64_t m, std::uint64_t period);

/// cos and sin of x radians, |x| ≤ kMaxTrigArgument (reduction by a three-part π/2).
CosSin cos_sin(double x);

/// Largest |x| cos_sin() accepts with full accuracy (validate() bounds line phases by it).
inline constexpr double kMaxTrigArgument = 1.0e6;

}  // namespace excite::signal
