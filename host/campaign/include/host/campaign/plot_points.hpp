// SPDX-License-Identifier: MIT
#pragma once
// What a figure can show of a curve (issue 23 §3). A panel W pixels wide shows at most W
// columns of a curve, and of each column only its lowest and highest value; a smooth stretch
// shows as a straight line within half a pixel. These functions keep exactly that — every
// peak a column shows, every point farther than the tolerance from the drawn line — so an
// SVG holds O(W) points per curve instead of one per sample.

#include <iosfwd>
#include <vector>

namespace excite::host {

struct PlotPoint {
  double x = 0.0;
  double y = 0.0;
};
using Polyline = std::vector<PlotPoint>;

/// Min/max per column: the samples (x[k], y[k]), x increasing, split into `columns` equal
/// spans of x; from each span its lowest and its highest sample, in order of x (one point
/// when they are the same sample). Non-finite y are kept as line breaks. With at most
/// 2·columns samples, every sample. Throws std::invalid_argument for columns < 1 or x and y
/// of different lengths.
Polyline min_max_columns(const std::vector<double>& x, const std::vector<double>& y, int columns);

/// The data range a panel shows and its size in pixels; log axes map log10 of the values
/// (values ≤ 0 on a log axis are breaks).
struct PixelFrame {
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;
  double width_px = 1.0, height_px = 1.0;
  bool log_x = false, log_y = false;
};

/// The frame spanning every finite point of `curves` (a zero-width range counts as 1).
PixelFrame frame_of(const std::vector<Polyline>& curves, double width_px, double height_px,
                    bool log_x = false, bool log_y = false);

/// Ramer–Douglas–Peucker in the frame's pixels: a point is dropped only when it lies within
/// `tolerance_px` of the simplified line, so every point farther away (a peak, a step's
/// corner) is kept; the first and last point of every unbroken stretch are kept, and
/// non-finite points stay as breaks.
Polyline simplify(const Polyline& line, const PixelFrame& frame, double tolerance_px = 0.5);

/// One gnuplot data block: "x y" lines, a blank line at each break, two blank lines after
/// it (the next block is `index k+1`). An empty curve is written as one undefined point so
/// the numbering of the blocks stays put.
void write_block(std::ostream& out, const Polyline& line);

}  // namespace excite::host
