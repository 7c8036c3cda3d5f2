// SPDX-License-Identifier: MIT
#include "host/measures/input_measures.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio_or_nan(double num, double den) {
  return den > 0.0 ? num / den : kNaN;
}

}  // namespace

ChannelMeasures measure_channel(const Eigen::Ref<const Eigen::VectorXd>& x) {
  const Eigen::Index n = x.size();
  if (n < 2) throw std::invalid_argument("measure_channel: a sequence needs at least 2 samples");

  ChannelMeasures m;
  m.min = x.minCoeff();
  m.max = x.maxCoeff();
  const double mean = x.mean();
  m.rms = std::sqrt(x.squaredNorm() / static_cast<double>(n));

  const Eigen::VectorXd steps = x.tail(n - 1) - x.head(n - 1);
  const double switches = static_cast<double>((steps.array() != 0.0).count());
  const double transitions = static_cast<double>(n - 1);
  m.phi = (1.0 - switches / transitions) * 100.0;
  m.max_step = steps.cwiseAbs().maxCoeff();
  const double max_step_sq = m.max_step * m.max_step;
  m.phi_smooth = max_step_sq > 0.0 ? 1.0 - steps.squaredNorm() / (transitions * max_step_sq) : 1.0;

  const double range = m.max - m.min;
  m.peak_factor = ratio_or_nan(range, 2.0 * std::sqrt(2.0) * m.rms);
  m.crest_factor = ratio_or_nan(x.cwiseAbs().maxCoeff(), m.rms);
  const double variance = std::max(0.0, m.rms * m.rms - mean * mean);
  m.pips = ratio_or_nan(200.0 * std::sqrt(variance), range);
  return m;
}

InputMeasures measure_inputs(const Eigen::Ref<const Eigen::MatrixXd>& table) {
  InputMeasures result;
  const Eigen::Index channels = table.cols();
  result.channels.reserve(static_cast<std::size_t>(channels));
  for (Eigen::Index c = 0; c < channels; ++c)
    result.channels.push_back(measure_channel(table.col(c)));

  ChannelMeasures& avg = result.average;
  for (const ChannelMeasures& m : result.channels) {
    avg.phi += m.phi;
    avg.phi_smooth += m.phi_smooth;
    avg.peak_factor += m.peak_factor;
    avg.rms += m.rms;
    avg.crest_factor += m.crest_factor;
    avg.pips += m.pips;
    avg.min += m.min;
    avg.max += m.max;
    avg.max_step += m.max_step;
  }
  const double count = static_cast<double>(std::max<Eigen::Index>(channels, 1));
  for (double* field : {&avg.phi, &avg.phi_smooth, &avg.peak_factor, &avg.rms, &avg.crest_factor,
                        &avg.pips, &avg.min, &avg.max, &avg.max_step}) {
    *field /= count;
  }
  return result;
}

double active_crest_factor_avg(const Eigen::Ref<const Eigen::MatrixXd>& table) {
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index j = 0; j < table.cols(); ++j) {
    Eigen::Index first = 0;
    Eigen::Index last = table.rows() - 1;
    while (first < table.rows() && table(first, j) == 0.0) ++first;
    if (first >= table.rows()) continue;  // this channel does not move
    while (table(last, j) == 0.0) --last;
    const auto span = table.col(j).segment(first, last - first + 1);
    const double rms = std::sqrt(span.squaredNorm() / static_cast<double>(span.size()));
    sum += span.cwiseAbs().maxCoeff() / rms;
    ++count;
  }
  return count > 0 ? sum / count : std::nan("");
}

}  // namespace excite::host
