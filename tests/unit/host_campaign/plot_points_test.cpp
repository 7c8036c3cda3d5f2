// SPDX-License-Identifier: MIT
// What a figure keeps of a curve (issue 23 §3): min/max per pixel column keeps every peak a
// column shows, and the simplification keeps every point farther than half a pixel from the
// drawn line — a long noisy series shrinks to O(columns) points and no spike is lost.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "host/campaign/plot_points.hpp"

namespace excite::host {
namespace {

std::vector<double> ramp(std::size_t n) {
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = static_cast<double>(k);
  return x;
}

bool contains(const Polyline& line, double x, double y) {
  for (const PlotPoint& p : line) {
    if (p.x == x && p.y == y) return true;
  }
  return false;
}

// GIVEN 15 080 samples of noise with one spike up and one down WHEN reduced to 700 columns
// THEN both spikes are points of the curve and at most two points per column remain.
TEST(MinMaxColumns, KeepsEverySpikeOfALongNoisySeriesAndAtMostTwoPointsPerColumn) {
  const std::size_t n = 15080;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> y(n);
  for (double& v : y) v = noise(rng);
  y[4321] = 5.0;
  y[9876] = -4.0;
  const Polyline line = min_max_columns(ramp(n), y, 700);
  EXPECT_LE(line.size(), 1400U);
  EXPECT_TRUE(contains(line, 4321.0, 5.0));
  EXPECT_TRUE(contains(line, 9876.0, -4.0));
  for (std::size_t k = 1; k < line.size(); ++k) EXPECT_LT(line[k - 1].x, line[k].x) << k;
}

TEST(MinMaxColumns, KeepsEverySampleOfAShortSeriesAndRefusesNoColumns) {
  const std::vector<double> y{1.0, -2.0, 3.0};
  EXPECT_EQ(min_max_columns(ramp(3), y, 2).size(), 3U);
  EXPECT_THROW(min_max_columns(ramp(3), y, 0), std::invalid_argument);
  EXPECT_THROW(min_max_columns(ramp(2), y, 2), std::invalid_argument);
}

// Every dropped point lies within the tolerance of the simplified line (in pixels), and a
// step's corners survive.
TEST(Simplify, DropsOnlyPointsWithinHalfAPixelAndKeepsAStepsCorners) {
  Polyline curve;
  for (int k = 0; k <= 400; ++k) {
    const double t = k;
    curve.push_back({t, (t >= 200.0 ? 1.0 : 0.0) + 0.3 * (1.0 - std::exp(-t / 50.0))});
  }
  const PixelFrame frame = frame_of({curve}, 260.0, 210.0);
  const Polyline kept = simplify(curve, frame);
  EXPECT_LT(kept.size(), 60U);
  EXPECT_TRUE(contains(kept, 199.0, curve[199].y));
  EXPECT_TRUE(contains(kept, 200.0, curve[200].y));
  // Interpolate the kept line at every original point: within 0.5 px (+ rounding).
  const double sx = 260.0 / (frame.x1 - frame.x0), sy = 210.0 / (frame.y1 - frame.y0);
  std::size_t j = 0;
  for (const PlotPoint& p : curve) {
    while (j + 1 < kept.size() && kept[j + 1].x < p.x) ++j;
    const PlotPoint& a = kept[j];
    const PlotPoint& b = kept[std::min(j + 1, kept.size() - 1)];
    // Distance from p to the segment a–b in pixels.
    const double ax = a.x * sx, ay = a.y * sy, bx = b.x * sx, by = b.y * sy;
    const double px = p.x * sx, py = p.y * sy;
    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
    const double u = l2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / l2, 0.0, 1.0) : 0.0;
    EXPECT_LE(std::hypot(px - ax - u * dx, py - ay - u * dy), 0.5 + 1e-9) << p.x;
  }
}

TEST(Simplify, KeepsBreaksAndTheEndsOfEveryStretch) {
  const Polyline curve{{0, 0}, {1, 0}, {2, 0}, {3, NAN}, {4, 1}, {5, 1}, {6, 1}};
  const Polyline kept = simplify(curve, frame_of({curve}, 100.0, 100.0));
  ASSERT_EQ(kept.size(), 5U);
  EXPECT_TRUE(std::isnan(kept[2].y));
  std::ostringstream out;
  write_block(out, kept);
  EXPECT_EQ(out.str(), "0 0\n2 0\n\n4 1\n6 1\n\n\n");
}

TEST(WriteBlock, AnEmptyCurveIsOneUndefinedPointSoTheBlocksKeepTheirNumbers) {
  std::ostringstream out;
  write_block(out, {});
  EXPECT_EQ(out.str(), "NaN NaN\n\n\n");
}

// Log axes: the tolerance is in pixels of the logarithmic axis; values ≤ 0 are breaks.
TEST(Simplify, WorksInTheLogarithmsOfALogLogPanel) {
  Polyline curve;
  for (int k = 0; k <= 120; ++k) {
    const double w = std::pow(10.0, -4.0 + 4.0 * k / 120.0);
    curve.push_back({w, 10.0 / std::sqrt(1.0 + 2500.0 * w * w)});
  }
  const Polyline kept = simplify(curve, frame_of({curve}, 260.0, 220.0, true, true));
  EXPECT_LT(kept.size(), 40U);
  EXPECT_GT(kept.size(), 3U);
}

}  // namespace
}  // namespace excite::host
