// SPDX-License-Identifier: MIT
#include "host/identify/segments.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/lti/difference_equation.hpp"

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

void simulate_sum_segments(std::span<const sim::DiscreteTerm* const> terms,
                           std::span<const double> gains,
                           std::span<const std::span<const double>> inputs, std::span<double> y,
                           const std::vector<Segment>& segments, std::vector<double>& scratch) {
  std::fill(y.begin(), y.end(), 0.0);
  constexpr std::size_t kGroup = sim::kMaxSideBySide;
  for (const Segment& s : segments) {
    const auto begin = static_cast<std::size_t>(s.begin);
    const auto n = static_cast<std::size_t>(s.end - s.begin);
    scratch.resize(kGroup * n);
    for (std::size_t first = 0; first < terms.size(); first += kGroup) {
      const std::size_t count = std::min(kGroup, terms.size() - first);
      std::array<const double*, kGroup> x{};
      for (std::size_t j = 0; j < count; ++j) {
        // The element's input delayed by its whole samples, zero before: its state stays
        // at rest (±0) until the input arrives, as simulate_term's offset start leaves it.
        double* delayed = scratch.data() + j * n;
        const std::size_t d =
            std::min(static_cast<std::size_t>(terms[first + j]->delay_samples), n);
        std::fill(delayed, delayed + d, 0.0);
        std::copy_n(inputs[first + j].data() + begin, n - d, delayed + d);
        x[j] = delayed;
      }
      sim::tdf2_accumulate_sum(terms.subspan(first, count), gains.subspan(first, count),
                               std::span<const double* const>(x.data(), count), y.data() + begin,
                               n);
    }
  }
}

namespace {

// G columns' all-pole recursions, one sample of each in turn (all_pole_filter's arithmetic).
template <std::size_t G>
void all_pole_side_by_side(const std::array<double, kMaxPoles>* a, double* const* x,
                           std::size_t count) {
  std::array<double, G> y1{};
  std::array<double, G> y2{};
  std::array<double, G> y3{};
  for (std::size_t k = 0; k < count; ++k) {
    for (std::size_t j = 0; j < G; ++j) {
      const double yk = ((x[j][k] - a[j][2] * y3[j]) - a[j][1] * y2[j]) - a[j][0] * y1[j];
      y3[j] = y2[j];
      y2[j] = y1[j];
      y1[j] = yk;
      x[j][k] = yk;
    }
  }
}

}  // namespace

void all_pole_filter_columns(std::span<const std::array<double, kMaxPoles>> a,
                             Eigen::Ref<Eigen::MatrixXd> x, const std::vector<Segment>& segments) {
  constexpr std::size_t kGroup = 4;
  const auto columns = static_cast<std::size_t>(x.cols());
  for (const Segment& s : segments) {
    const auto n = static_cast<std::size_t>(s.end - s.begin);
    for (std::size_t first = 0; first < columns; first += kGroup) {
      const std::size_t count = std::min(kGroup, columns - first);
      std::array<double*, kGroup> p{};
      for (std::size_t j = 0; j < count; ++j)
        p[j] = x.col(static_cast<Eigen::Index>(first + j)).data() + s.begin;
      const std::array<double, kMaxPoles>* coefficients = a.data() + first;
      switch (count) {
        case 1:
          all_pole_side_by_side<1>(coefficients, p.data(), n);
          break;
        case 2:
          all_pole_side_by_side<2>(coefficients, p.data(), n);
          break;
        case 3:
          all_pole_side_by_side<3>(coefficients, p.data(), n);
          break;
        default:
          all_pole_side_by_side<4>(coefficients, p.data(), n);
          break;
      }
    }
  }
}

void lagged_sum(Eigen::Ref<Eigen::VectorXd> dst, std::span<const LaggedTerm> terms,
                const std::vector<Segment>& segments) {
  // Blocks of eight rows: four independent sums of two, so the additions overlap.
  using Block = Eigen::Array<double, 8, 1>;
  constexpr Eigen::Index kRows = Block::RowsAtCompileTime;
  Eigen::Index longest = 0;
  for (const LaggedTerm& t : terms) longest = std::max(longest, t.lag);
  for (const Segment& s : segments) {
    // Rows at which every term's source lies in the segment are summed by blocks in
    // registers; the rows before (and a tail) term by term with the segment test.
    const Eigen::Index full = std::min(s.begin + longest, s.end);
    const auto one_by_one = [&](Eigen::Index k) {
      double sum = 0.0;
      for (const LaggedTerm& t : terms) {
        if (k - t.lag >= s.begin) sum += t.c * t.src[k - t.lag];
      }
      dst(k) = sum;
    };
    for (Eigen::Index k = s.begin; k < full; ++k) one_by_one(k);
    Eigen::Index k = full;
    for (; k + kRows <= s.end; k += kRows) {
      Block sum = Block::Zero();
      for (const LaggedTerm& t : terms) sum += t.c * Eigen::Map<const Block>(t.src + k - t.lag);
      Eigen::Map<Block>(dst.data() + k) = sum;
    }
    for (; k < s.end; ++k) one_by_one(k);
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
