// SPDX-License-Identifier: MIT
#include "host/import/import_run.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "base/config/document.hpp"
#include "firmware/runlog/format.hpp"
#include "firmware/runlog/writer.hpp"
#include "host/import/timestamp.hpp"

namespace excite::host::historian {
namespace {

// The first and last sample over all tags (each tag's times increase).
void span_of(const HistorianData& d, double& first, double& last) {
  first = d.series.front().time_s.front();
  last = d.series.front().time_s.back();
  for (const TagSeries& s : d.series) {
    first = std::min(first, s.time_s.front());
    last = std::max(last, s.time_s.back());
  }
}

// The spacing of the samples: the median over every tag's consecutive times.
double spacing_of(const HistorianData& d) {
  std::vector<double> pooled;
  for (const TagSeries& s : d.series) {
    for (std::size_t i = 1; i < s.time_s.size(); ++i) {
      pooled.push_back(s.time_s[i] - s.time_s[i - 1]);
    }
  }
  if (pooled.empty()) return 0.0;
  const auto mid = pooled.begin() + static_cast<std::ptrdiff_t>(pooled.size() / 2);
  std::nth_element(pooled.begin(), mid, pooled.end());
  return *mid;
}

// Refuses a grid of more than max_rows rows before it is allocated, naming the line of the
// timestamp farthest from the middle of the record (a mistyped year, a year of data).
void check_grid_rows(const HistorianData& d, double first, double last, double T_s, double T_min,
                     std::size_t max_rows) {
  const double rows = std::floor((last - first) / T_s + 1e-9) + 1.0;
  if (rows <= static_cast<double>(max_rows)) return;
  const TagSeries& s0 = d.series.front();
  const double middle = s0.time_s[(s0.time_s.size() - 1) / 2];
  double far = s0.time_s.front();
  std::size_t far_line = s0.line.front();
  for (const TagSeries& s : d.series) {
    for (const std::size_t i : {std::size_t{0}, s.time_s.size() - 1}) {
      if (std::fabs(s.time_s[i] - middle) >= std::fabs(far - middle)) {  // a tie: the end
        far = s.time_s[i];
        far_line = s.line[i];
      }
    }
  }
  char count[32];
  std::snprintf(count, sizeof count, "%.0f", rows);
  throw std::invalid_argument(
      d.file + ":" + std::to_string(far_line) + ": time = " + format_utc(far) +
      ", expected a record of at most " + std::to_string(max_rows) + " rows of " +
      config::format_number(T_min) + " min (the run log's limit): from " + format_utc(first) +
      " to " + format_utc(last) + " is " + count +
      " rows; give --from/--to (a time window) or a longer --sample-time-min");
}

// A uniform grid from the first timestamp to the last.
std::vector<double> grid_of(double first, double last, double T_s) {
  std::vector<double> g;
  const double span = last - first;
  const auto n = static_cast<std::size_t>(std::floor(span / T_s + 1e-9)) + 1;
  g.reserve(n);
  for (std::size_t k = 0; k < n; ++k) g.push_back(first + static_cast<double>(k) * T_s);
  return g;
}

double baseline_of(const std::vector<double>& v, std::size_t from, std::size_t to,
                   const TagSpec& tag, const std::string& file, const ImportOptions& o) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = from; k <= to && k < v.size(); ++k) {
    if (!std::isnan(v[k])) {
      sum += v[k];
      ++n;
    }
  }
  if (n == 0) {
    throw std::invalid_argument(file + ": tag '" + tag.tag +
                                "' has no good value in the baseline "
                                "window " +
                                config::format_number(o.baseline_from_min) + " … " +
                                config::format_number(o.baseline_to_min) +
                                " min from the data's start, expected at least one (give "
                                "--baseline FROM:TO)");
  }
  return sum / static_cast<double>(n);
}

// Range (max − min) of the good values.
double range_of(const std::vector<double>& v) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double x : v) {
    if (std::isnan(x)) continue;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return hi >= lo ? hi - lo : 0.0;
}

// The offset or line removed from the good rows of dy (NaN rows ignored).
void detrend(std::vector<double>& dy, Detrend mode, double T_min, double& offset, double& slope) {
  offset = 0.0;
  slope = 0.0;
  if (mode == Detrend::none) return;
  std::vector<Eigen::Index> good;
  for (std::size_t k = 0; k < dy.size(); ++k) {
    if (!std::isnan(dy[k])) good.push_back(static_cast<Eigen::Index>(k));
  }
  if (good.empty()) return;
  const auto m = static_cast<Eigen::Index>(good.size());
  Eigen::MatrixXd A(m, mode == Detrend::linear ? 2 : 1);
  Eigen::VectorXd b(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    A(i, 0) = 1.0;
    if (A.cols() > 1) A(i, 1) = static_cast<double>(good[static_cast<std::size_t>(i)]) * T_min;
    b(i) = dy[static_cast<std::size_t>(good[static_cast<std::size_t>(i)])];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  offset = c(0);
  slope = A.cols() > 1 ? c(1) : 0.0;
  for (std::size_t k = 0; k < dy.size(); ++k) {
    dy[k] -= offset + slope * static_cast<double>(k) * T_min;
  }
}

}  // namespace

AutoBaseline auto_baseline(const std::vector<std::vector<double>>& values, std::size_t mvs,
                           double T_min, double tau_high_min) {
  AutoBaseline out;
  const std::size_t N = values.empty() ? 0 : values.front().size();
  // The first MV move.
  std::size_t first_move = N;
  for (std::size_t i = 0; i < mvs && i < values.size(); ++i) {
    const std::vector<double>& v = values[i];
    const double tolerance = 1e-3 * range_of(v);
    double first = std::nan("");
    for (std::size_t k = 0; k < N && k < first_move; ++k) {
      if (std::isnan(v[k])) continue;
      if (std::isnan(first)) first = v[k];
      if (std::abs(v[k] - first) > tolerance) first_move = k;
    }
  }
  const std::size_t needed = std::max<std::size_t>(
      2, tau_high_min > 0.0 ? static_cast<std::size_t>(std::ceil(tau_high_min / T_min))
                            : std::min<std::size_t>(60, N / 10));
  std::string why;
  if (first_move < needed) {
    why = "the MVs move " + config::format_number(static_cast<double>(first_move) * T_min) +
          " min after the start, before a steady window of " +
          config::format_number(static_cast<double>(needed) * T_min) + " min";
  } else {
    for (std::size_t c = mvs; c < values.size() && why.empty(); ++c) {
      // The CV's least-squares line over the window: its rise over the window.
      double sk = 0, sy = 0, skk = 0, sky = 0, n = 0;
      for (std::size_t k = 0; k < first_move; ++k) {
        const double y = values[c][k];
        if (std::isnan(y)) continue;
        const auto x = static_cast<double>(k);
        sk += x;
        sy += y;
        skk += x * x;
        sky += x * y;
        n += 1;
      }
      const double denominator = n * skk - sk * sk;
      const double slope = denominator > 0.0 ? (n * sky - sk * sy) / denominator : 0.0;
      const double rise = std::abs(slope) * static_cast<double>(first_move);
      if (rise > 0.1 * range_of(values[c])) {
        why = "CV " + std::to_string(c - mvs + 1) + " drifts by " + config::format_number(rise) +
              " before the first MV move";
      }
    }
  }
  if (why.empty()) {
    out.at_rest = true;
    out.steady_rows = first_move;
    out.note = "steady window 0 … " +
               config::format_number(static_cast<double>(first_move) * T_min) +
               " min before the first MV move";
  } else {
    out.note = "start not at rest (" + why +
               "): baselines are the record's mean; identify estimates the initial state";
  }
  return out;
}

namespace {

// The MVs then the CVs, one per tag read: valid unique channel names and units, each tag
// with samples. Throws naming the tag.
std::vector<TagSpec> checked_tags(const HistorianData& data, const ImportOptions& o) {
  std::vector<TagSpec> all = o.mvs;
  all.insert(all.end(), o.cvs.begin(), o.cvs.end());
  if (all.size() != data.series.size()) {
    throw std::invalid_argument(data.file + ": read " + std::to_string(data.series.size()) +
                                " tags, expected " + std::to_string(all.size()));
  }
  for (std::size_t a = 0; a < all.size(); ++a) {
    if (!runlog::valid_channel_name(all[a].name)) {
      throw std::invalid_argument("tag '" + all[a].tag + "': channel name '" + all[a].name +
                                  "' is not valid, expected letters, digits, _ . - (give a name "
                                  "in the --map file)");
    }
    if (!runlog::valid_unit(all[a].unit)) {
      throw std::invalid_argument("tag '" + all[a].tag + "': unit '" + all[a].unit +
                                  "' is not valid, expected no spaces, commas or '=' ('-' when "
                                  "dimensionless)");
    }
    for (std::size_t b = 0; b < a; ++b) {
      if (all[b].name == all[a].name) {
        throw std::invalid_argument("tags '" + all[b].tag + "' and '" + all[a].tag +
                                    "' both become channel '" + all[a].name +
                                    "', expected unique names");
      }
    }
  }
  for (std::size_t a = 0; a < all.size(); ++a) {
    if (data.series[a].time_s.empty()) {
      throw std::invalid_argument(data.file + ": tag '" + all[a].tag +
                                  "' has no samples, expected at least one");
    }
  }
  return all;
}

// Bad points (NaN deviations): flagged bad_value, the last good deviation held (0 before
// the first good one); the first row after a bad MV stretch flagged discontinuity.
void mark_bad_points(std::vector<std::vector<double>>& dev, std::size_t mvs, ImportedRun& run) {
  const std::size_t N = run.flags.size();
  std::vector<bool> mv_bad(N, false);
  run.bad_points.assign(dev.size(), 0);
  for (std::size_t a = 0; a < dev.size(); ++a) {
    double last = 0.0;
    for (std::size_t k = 0; k < N; ++k) {
      if (std::isnan(dev[a][k])) {
        run.flags[k] |= runlog::kBadValue;
        if (a < mvs) mv_bad[k] = true;
        ++run.bad_points[a];
        dev[a][k] = last;
      } else {
        last = dev[a][k];
      }
    }
  }
  for (std::size_t k = 1; k < N; ++k) {
    if (mv_bad[k - 1] && !mv_bad[k]) {
      run.flags[k] |= runlog::kDiscontinuity;
      ++run.discontinuities;
    }
  }
  for (const std::uint32_t f : run.flags) run.bad_rows += (f & runlog::kBadValue) != 0U ? 1U : 0U;
}

// The run's channels: MVs absolute and as deviations, CVs as deviations, with baselines.
void set_channels(const std::vector<double>& base, const std::vector<std::vector<double>>& dev,
                  const ImportOptions& o, ImportedRun& run) {
  const std::size_t N = run.flags.size();
  for (std::size_t i = 0; i < o.mvs.size(); ++i) {
    run.input_baseline.push_back(base[i]);
    run.du.push_back(dev[i]);
    std::vector<double> u(N);
    for (std::size_t k = 0; k < N; ++k) u[k] = base[i] + dev[i][k];
    run.u.push_back(std::move(u));
  }
  for (std::size_t j = 0; j < o.cvs.size(); ++j) {
    run.output_baseline.push_back(base[o.mvs.size() + j]);
    run.dy.push_back(dev[o.mvs.size() + j]);
  }
}

// --max-gap-min and --baseline FROM:TO, the window inside the data's span (minutes) before
// any minutes become sample indices (1e300 once went through an out-of-range double →
// size_t conversion). Throws naming the option.
void check_window_options(const ImportOptions& o, double span_min) {
  if (!(o.max_gap_min >= 0.0) || !std::isfinite(o.max_gap_min)) {
    throw std::invalid_argument("--max-gap-min " + config::format_number(o.max_gap_min) +
                                ", expected a finite number ≥ 0 (0: 1.5 sample times)");
  }
  if (!(o.baseline_from_min >= 0.0) || !(o.baseline_to_min >= o.baseline_from_min)) {
    throw std::invalid_argument("--baseline " + config::format_number(o.baseline_from_min) + ":" +
                                config::format_number(o.baseline_to_min) +
                                ", expected 0 ≤ FROM ≤ TO minutes from the data's start");
  }
  if (!(o.baseline_from_min <= span_min)) {
    throw std::invalid_argument("--baseline " + config::format_number(o.baseline_from_min) + ":" +
                                config::format_number(o.baseline_to_min) +
                                "; FROM = " + config::format_number(o.baseline_from_min) +
                                " min, expected at most " + config::format_number(span_min) +
                                " min (the data's span)");
  }
}

}  // namespace

ImportedRun import_historian(const HistorianData& data, const ImportOptions& o) {
  if (o.mvs.empty() || o.cvs.empty()) {
    throw std::invalid_argument(data.file + ": " + std::to_string(o.mvs.size()) + " MVs and " +
                                std::to_string(o.cvs.size()) +
                                " CVs, expected at least one of each (--mv, --cv or --map)");
  }
  const std::vector<TagSpec> all = checked_tags(data, o);
  double t_first = 0.0, t_last = 0.0;
  span_of(data, t_first, t_last);
  const double spacing_s = spacing_of(data);
  double T_min = o.sample_time_min;
  if (T_min == 0.0) T_min = spacing_s / 60.0;
  if (!(T_min > 0.0) || !std::isfinite(T_min)) {
    throw std::invalid_argument(data.file + ": sample time " + config::format_number(T_min) +
                                " min, expected > 0 (give --sample-time-min; the data have " +
                                std::to_string(data.series.front().time_s.size()) + " rows)");
  }
  const double T_s = T_min * 60.0;
  check_grid_rows(data, t_first, t_last, T_s, T_min, o.max_rows);
  const std::vector<double> grid = grid_of(t_first, t_last, T_s);
  if (grid.size() < 2) {
    throw std::invalid_argument(data.file + ": the data span " +
                                config::format_number(t_last - t_first) +
                                " s, less than two samples of " + config::format_number(T_min) +
                                " min, expected a longer record or a shorter --sample-time-min");
  }
  const double span_min = static_cast<double>(grid.size() - 1) * T_min;
  check_window_options(o, span_min);
  const double gap_limit =
      o.max_gap_min > 0.0 ? 60.0 * o.max_gap_min : 1.5 * std::max(T_s, spacing_s);
  const double to_min = std::min(o.baseline_to_min, span_min);
  auto b_from = static_cast<std::size_t>(std::ceil(o.baseline_from_min / T_min - 1e-9));
  auto b_to = static_cast<std::size_t>(std::floor(to_min / T_min + 1e-9));

  ImportedRun run;
  run.time_scales = o.time_scales;
  run.sample_time_min = T_min;
  run.inputs = o.mvs;
  run.outputs = o.cvs;
  const std::size_t N = grid.size();
  run.flags.assign(N, 0U);
  std::vector<std::vector<double>> values(all.size());
  for (std::size_t a = 0; a < all.size(); ++a) {
    values[a] = resample(data.series[a].time_s, data.series[a].values, grid, o.resample, gap_limit);
  }
  if (o.baseline_auto) {
    const AutoBaseline ab = auto_baseline(values, o.mvs.size(), T_min, o.time_scales.tau_high_min);
    run.start_at_rest = ab.at_rest;
    run.baseline_note = ab.note;
    b_from = 0;
    b_to = ab.at_rest ? ab.steady_rows - 1 : N - 1;
  } else {
    run.baseline_note = "window " + config::format_number(o.baseline_from_min) + " … " +
                        config::format_number(o.baseline_to_min) + " min (--baseline)";
  }
  std::vector<std::vector<double>> dev(all.size());
  std::vector<double> base(all.size());
  for (std::size_t a = 0; a < all.size(); ++a) {
    const std::vector<double>& v = values[a];
    base[a] = baseline_of(v, b_from, b_to, all[a], data.file, o);
    dev[a].resize(N);
    for (std::size_t k = 0; k < N; ++k) dev[a][k] = v[k] - base[a];  // NaN stays NaN
  }
  for (std::size_t j = 0; j < o.cvs.size(); ++j) {
    double offset = 0.0, slope = 0.0;
    detrend(dev[o.mvs.size() + j], o.detrend, T_min, offset, slope);
    run.removed_offset.push_back(offset);
    run.removed_slope_per_min.push_back(slope);
  }
  mark_bad_points(dev, o.mvs.size(), run);
  set_channels(base, dev, o, run);
  return run;
}

std::string run_log_text(const ImportedRun& run, const std::string& source) {
  std::vector<runlog::Channel> inputs, outputs;
  for (const auto& t : run.inputs) inputs.push_back({t.name, t.unit});
  for (const auto& t : run.outputs) outputs.push_back({t.name, t.unit});
  const std::string plant = "historian " + source;
  const std::string producer = "excite import " + std::string(runlog::kVersion);
  runlog::Header header{plant, "excite import", run.sample_time_min, inputs, outputs};
  header.producer = producer;
  header.time_scales = run.time_scales;
  header.baseline = run.baseline_note;
  header.start_at_rest = run.start_at_rest;
  std::string text;
  std::vector<char> buffer(64 * 1024 + 64 * (inputs.size() + outputs.size()));
  const runlog::WriteResult h = runlog::format_header(header, buffer);
  if (h.status != runlog::WriteStatus::ok) {
    throw std::invalid_argument("run log header: " + std::string(runlog::describe(h.status)));
  }
  text.append(buffer.data(), h.length);
  const std::size_t n = inputs.size();
  const std::size_t p = outputs.size();
  std::vector<double> du(n), u(n), dy(p);
  std::vector<char> row_buffer(runlog::max_row_chars(n, p));
  for (std::size_t k = 0; k < run.rows(); ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      du[i] = run.du[i][k];
      u[i] = run.u[i][k];
    }
    for (std::size_t j = 0; j < p; ++j) dy[j] = run.dy[j][k];
    runlog::Row row;
    row.t_min = static_cast<double>(k) * run.sample_time_min;
    row.k = k;
    row.du = du;
    row.u = u;
    row.dy = dy;
    row.flags = run.flags[k];
    const runlog::WriteResult r = runlog::format_row(header, row, row_buffer);
    if (r.status != runlog::WriteStatus::ok) {
      throw std::invalid_argument("run log row " + std::to_string(k) + ": " +
                                  std::string(runlog::describe(r.status)));
    }
    text.append(row_buffer.data(), r.length);
  }
  return text;
}

}  // namespace excite::host::historian
