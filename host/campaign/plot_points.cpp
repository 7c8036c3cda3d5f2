// SPDX-License-Identifier: MIT
#include "host/campaign/plot_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <stdexcept>

namespace excite::host {
namespace {

bool finite(const PlotPoint& p) {
  return std::isfinite(p.x) && std::isfinite(p.y);
}

double axis(double v, bool log) {
  if (!log) return v;
  return v > 0.0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN();
}

// Pixel coordinates of a point in the frame (NaN when it cannot be drawn).
PlotPoint pixel(const PlotPoint& p, const PixelFrame& f) {
  const double x0 = axis(f.x0, f.log_x), x1 = axis(f.x1, f.log_x);
  const double y0 = axis(f.y0, f.log_y), y1 = axis(f.y1, f.log_y);
  const double sx = x1 > x0 ? f.width_px / (x1 - x0) : 1.0;
  const double sy = y1 > y0 ? f.height_px / (y1 - y0) : 1.0;
  return {(axis(p.x, f.log_x) - x0) * sx, (axis(p.y, f.log_y) - y0) * sy};
}

double distance_to_segment(const PlotPoint& p, const PlotPoint& a, const PlotPoint& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

// Marks the points of px[first..last] to keep (iterative, no recursion depth limit).
void rdp(const std::vector<PlotPoint>& px, std::size_t first, std::size_t last, double tolerance,
         std::vector<char>& keep) {
  std::vector<std::pair<std::size_t, std::size_t>> stack{{first, last}};
  keep[first] = keep[last] = 1;
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = -1.0;
    std::size_t at = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d = distance_to_segment(px[k], px[a], px[b]);
      if (d > worst) {
        worst = d;
        at = k;
      }
    }
    if (worst > tolerance) {
      keep[at] = 1;
      stack.emplace_back(a, at);
      stack.emplace_back(at, b);
    }
  }
}

}  // namespace

Polyline min_max_columns(const std::vector<double>& x, const std::vector<double>& y, int columns) {
  if (columns < 1) throw std::invalid_argument("min_max_columns: columns < 1, expected >= 1");
  if (x.size() != y.size()) {
    throw std::invalid_argument("min_max_columns: x and y differ in length, expected equal");
  }
  const std::size_t n = x.size();
  Polyline out;
  if (n <= 2 * static_cast<std::size_t>(columns)) {
    for (std::size_t k = 0; k < n; ++k) out.push_back({x[k], y[k]});
    return out;
  }
  const double x0 = x.front(), span = x.back() - x.front();
  const auto column_of = [&](std::size_t k) {
    return span > 0.0 ? std::min(columns - 1, static_cast<int>((x[k] - x0) / span * columns)) : 0;
  };
  std::size_t k = 0;
  while (k < n) {
    if (!std::isfinite(y[k])) {  // a break
      out.push_back({x[k], y[k]});
      ++k;
      continue;
    }
    // The samples of k's column up to the next break: their lowest and highest, in order.
    const int column = column_of(k);
    std::size_t lo = k, hi = k, end = k;
    for (; end < n && std::isfinite(y[end]) && column_of(end) == column; ++end) {
      if (y[end] < y[lo]) lo = end;
      if (y[end] > y[hi]) hi = end;
    }
    const std::size_t a = std::min(lo, hi), b = std::max(lo, hi);
    out.push_back({x[a], y[a]});
    if (b != a) out.push_back({x[b], y[b]});
    k = end;
  }
  return out;
}

PixelFrame frame_of(const std::vector<Polyline>& curves, double width_px, double height_px,
                    bool log_x, bool log_y) {
  PixelFrame f;
  f.width_px = width_px;
  f.height_px = height_px;
  f.log_x = log_x;
  f.log_y = log_y;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Polyline& c : curves) {
    for (const PlotPoint& p : c) {
      if (!finite(p) || (log_x && p.x <= 0.0) || (log_y && p.y <= 0.0)) continue;
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
  }
  if (!(x0 <= x1)) x0 = 0.0, x1 = 1.0;
  if (!(y0 <= y1)) y0 = 0.0, y1 = 1.0;
  if (x1 == x0) x1 = log_x ? x0 * 10.0 : x0 + 1.0;
  if (y1 == y0) y1 = log_y ? y0 * 10.0 : y0 + 1.0;
  f.x0 = x0;
  f.x1 = x1;
  f.y0 = y0;
  f.y1 = y1;
  return f;
}

Polyline simplify(const Polyline& line, const PixelFrame& frame, double tolerance_px) {
  std::vector<PlotPoint> px(line.size());
  std::vector<char> drawable(line.size());
  for (std::size_t k = 0; k < line.size(); ++k) {
    px[k] = pixel(line[k], frame);
    drawable[k] = finite(px[k]);
  }
  std::vector<char> keep(line.size(), 0);
  std::size_t k = 0;
  while (k < line.size()) {
    if (!drawable[k]) {
      keep[k] = 1;  // a break
      ++k;
      continue;
    }
    std::size_t end = k;
    while (end + 1 < line.size() && drawable[end + 1]) ++end;
    rdp(px, k, end, tolerance_px, keep);
    k = end + 1;
  }
  Polyline out;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (keep[i]) out.push_back(line[i]);
  }
  return out;
}

void write_block(std::ostream& out, const Polyline& line) {
  bool any = false, pending_break = false;
  for (const PlotPoint& p : line) {
    if (!finite(p)) {
      pending_break = any;
      continue;
    }
    if (pending_break) out << '\n';  // one blank line: a break in the curve
    out << p.x << ' ' << p.y << '\n';
    any = true;
    pending_break = false;
  }
  if (!any) out << "NaN NaN\n";
  out << "\n\n";
}

}  // namespace excite::host
