// SPDX-License-Identifier: MIT
#include "host/identify/segments.hpp"

#include <cmath>

#include <stdexcept>
#include <string>

namespace excite::host {

SampleLayout SampleLayout::whole(Eigen::Index rows) {
  SampleLayout l;
  l.segments.push_back(Segment{0, rows});
  l.weight = Eigen::VectorXd::Ones(rows);
  return l;
}

Eigen::Index SampleLayout::scored() const {
  Eigen::Index n = 0;
  for (Eigen::Index k = 0; k < weight.size(); ++k) n += weight(k) != 0.0 ? 1 : 0;
  return n;
}

void SampleLayout::check() const {
  Eigen::Index next = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Segment& g = segments[s];
    if (g.begin != next || g.end <= g.begin) {
      throw std::invalid_argument("identify: segment " + std::to_string(s + 1) + " is rows [" +
                                  std::to_string(g.begin) + ", " + std::to_string(g.end) +
                                  "), expected a non-empty span starting at row " +
                                  std::to_string(next));
    }
    next = g.end;
  }
  if (next != rows()) {
    throw std::invalid_argument("identify: the segments cover " + std::to_string(next) +
                                " rows, expected all " + std::to_string(rows()));
  }
  for (Eigen::Index k = 0; k < rows(); ++k) {
    if (weight(k) != 0.0 && weight(k) != 1.0) {
      throw std::invalid_argument("identify: weight of row " + std::to_string(k) + " is " +
                                  std::to_string(weight(k)) + ", expected 0 or 1");
    }
  }
}

Eigen::VectorXd SampleLayout::scored_rows(const Eigen::VectorXd& v) const {
  Eigen::VectorXd out(scored());
  Eigen::Index i = 0;
  for (Eigen::Index k = 0; k < weight.size(); ++k) {
    if (weight(k) != 0.0) out(i++) = v(k);
  }
  return out;
}

Eigen::MatrixXd SampleLayout::scored_rows(const Eigen::MatrixXd& M, Eigen::Index begin,
                                          Eigen::Index end) const {
  Eigen::Index n = 0;
  for (Eigen::Index k = begin; k < end; ++k) n += weight(k) != 0.0 ? 1 : 0;
  Eigen::MatrixXd out(n, M.cols());
  Eigen::Index r = 0;
  for (Eigen::Index k = begin; k < end; ++k) {
    if (weight(k) != 0.0) out.row(r++) = M.row(k);
  }
  return out;
}

Eigen::MatrixXd scored_about_segment_means(const Eigen::MatrixXd& Y, const SampleLayout& layout) {
  Eigen::MatrixXd out(layout.scored(), Y.cols());
  Eigen::Index at = 0;
  for (const Segment& s : layout.segments) {
    Eigen::MatrixXd part = layout.scored_rows(Y, s.begin, s.end);
    if (part.rows() == 0) continue;
    part.rowwise() -= part.colwise().mean();
    out.middleRows(at, part.rows()) = part;
    at += part.rows();
  }
  return out;
}

Eigen::MatrixXd trend_basis(const SampleLayout& layout, Trend trend,
                            const std::vector<double>& transient_samples) {
  const Eigen::Index N = layout.rows();
  if (trend == Trend::none && transient_samples.empty()) return Eigen::MatrixXd(N, 0);
  std::vector<Eigen::VectorXd> columns;
  for (const Segment& s : layout.segments) {
    const Eigen::Index n = s.end - s.begin;
    if (layout.weight.segment(s.begin, n).sum() == 0.0) continue;
    Eigen::VectorXd one = Eigen::VectorXd::Zero(N);
    one.segment(s.begin, n) = layout.weight.segment(s.begin, n);
    columns.push_back(one);
    for (const double tau : transient_samples) {
      if (!(tau <= 0.5 * static_cast<double>(n))) continue;  // no decay to tell from the offset
      Eigen::VectorXd decay = Eigen::VectorXd::Zero(N);
      for (Eigen::Index k = 0; k < n; ++k) {
        decay(s.begin + k) = layout.weight(s.begin + k) * std::exp(-static_cast<double>(k) / tau);
      }
      columns.push_back(decay);
    }
    if (trend == Trend::linear && layout.weight.segment(s.begin, n).sum() >= 2.0) {
      Eigen::VectorXd ramp = Eigen::VectorXd::Zero(N);
      for (Eigen::Index k = 0; k < n; ++k) {
        ramp(s.begin + k) =
            layout.weight(s.begin + k) * static_cast<double>(k) / static_cast<double>(n);
      }
      columns.push_back(ramp);
    }
  }
  Eigen::MatrixXd B(N, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) B.col(static_cast<Eigen::Index>(c)) = columns[c];
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(B);
  return qr.householderQ() * Eigen::MatrixXd::Identity(N, B.cols());
}

void simulate_segments(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y,
                       const std::vector<Segment>& segments) {
  for (const Segment& s : segments) {
    const auto b = static_cast<std::size_t>(s.begin);
    const auto n = static_cast<std::size_t>(s.end - s.begin);
    simulate(g, u.subspan(b, n), y.subspan(b, n));
  }
}

void all_pole_filter_segments(const std::array<double, kMaxPoles>& a, std::span<double> x,
                              const std::vector<Segment>& segments) {
  for (const Segment& s : segments) {
    all_pole_filter(
        a, x.subspan(static_cast<std::size_t>(s.begin), static_cast<std::size_t>(s.end - s.begin)));
  }
}

void add_lagged(Eigen::Ref<Eigen::VectorXd> dst, const Eigen::VectorXd& src, Eigen::Index lag,
                double c, const std::vector<Segment>& segments) {
  for (const Segment& s : segments) {
    const Eigen::Index n = s.end - s.begin - lag;
    if (n > 0) dst.segment(s.begin + lag, n) += c * src.segment(s.begin, n);
  }
}

}  // namespace excite::host
