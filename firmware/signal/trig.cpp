// SPDX-License-Identifier: MIT
#include "firmware/signal/trig.hpp"

#include <cmath>

namespace excite::signal {
namespace {

constexpr double kQuarterPi = 0.78539816339744830962;
constexpr double kTwoOverPi = 0.63661977236758134308;
// π/2 = kPio2Hi + kPio2Mid + kPio2Lo; the first two have 33 significant bits, so
// n · kPio2Hi and n · kPio2Mid are exact for |n| < 2^20 (the fdlibm splitting).
constexpr double kPio2Hi = 1.57079632673412561417e+00;
constexpr double kPio2Mid = 6.07710050630396597660e-11;
constexpr double kPio2Lo = 2.02226624879595063154e-21;

// Taylor series of sin and cos on |x| ≤ π/4 (+ a little): the first omitted terms,
// x^19/19! and x^18/18!, are below 3e-18.
double sin_kernel(double x) {
  const double z = x * x;
  const double p =
      -1.0 / 6.0 +
      z * (1.0 / 120.0 +
           z * (-1.0 / 5040.0 +
                z * (1.0 / 362880.0 +
                     z * (-1.0 / 39916800.0 +
                          z * (1.0 / 6227020800.0 +
                               z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
  return x + x * z * p;
}

double cos_kernel(double x) {
  const double z = x * x;
  const double p =
      1.0 / 24.0 +
      z * (-1.0 / 720.0 +
           z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 + z * (1.0 / 479001600.0 +
                                                             z * (-1.0 / 87178291200.0 +
                                                                  z * (1.0 / 20922789888000.0))))));
  return 1.0 - 0.5 * z + z * z * p;
}

// cos and sin of quadrant · π/2 + x.
CosSin rotate_by_quadrants(std::uint64_t quadrant, double x) {
  const double c = cos_kernel(x);
  const double s = sin_kernel(x);
  switch (quadrant & 3U) {
    case 0:
      return {c, s};
    case 1:
      return {-s, c};
    case 2:
      return {-c, -s};
    default:
      return {s, -c};
  }
}

}  // namespace

CosSin cos_sin_turn(std::uint64_t m, std::uint64_t period) {
  // angle = 2π m / P = (π/4) · 8m / P = (π/4) · (octant + r / P), exactly in integers.
  const std::uint64_t reduced = m % period;
  const std::uint64_t eighths = 8U * reduced;
  const std::uint64_t octant = eighths / period;
  const std::uint64_t r = eighths - octant * period;
  if ((octant & 1U) == 0U) {
    const double x = kQuarterPi * (static_cast<double>(r) / static_cast<double>(period));
    return rotate_by_quadrants(octant / 2U, x);
  }
  // Odd octant: angle = (octant + 1) · π/4 − x with x = (π/4) (P − r) / P.
  const double x = kQuarterPi * (static_cast<double>(period - r) / static_cast<double>(period));
  return rotate_by_quadrants((octant + 1U) / 2U, -x);
}

CosSin cos_sin(double x) {
  const double n = std::floor(x * kTwoOverPi + 0.5);
  const double r = ((x - n * kPio2Hi) - n * kPio2Mid) - n * kPio2Lo;
  const auto quadrant = static_cast<std::uint64_t>(static_cast<std::int64_t>(n));
  return rotate_by_quadrants(quadrant, r);
}

}  // namespace excite::signal
