// SPDX-License-Identifier: MIT
#include "host/identify/own_part_start.hpp"

#include <cmath>
#include <mutex>
#include <optional>
#include <utility>

#include "host/identify/miso_fit.hpp"

namespace excite::host {

struct OwnPartStarts::Side {
  Side(const Eigen::MatrixXd& U, const std::vector<int>& inputs_, std::size_t a_, std::size_t b_,
       double T_min_, double max_delay_min_, const SampleLayout& layout_)
      : a(a_),
        b(b_),
        beta(beta_of(U, inputs_, layout_)),
        U_own(own_part(U, inputs_)),
        inputs(inputs_),
        T_min(T_min_),
        max_delay_min(max_delay_min_),
        layout(layout_) {}

  // The ARX basis on U_own, built on first use (a row whose cold end fits noise-free data
  // needs none; on a long run its QR is seconds). Thread-safe.
  const ArxBasis& arx() const {
    std::call_once(built, [&] { basis.emplace(U_own, inputs, T_min, max_delay_min, layout); });
    return *basis;
  }

  // b's least-squares multiple of a over the scored rows.
  double beta_of(const Eigen::MatrixXd& U, const std::vector<int>& columns,
                 const SampleLayout& scored) const {
    const Eigen::VectorXd ua = scored.scored_rows(U.col(columns[a]));
    const Eigen::VectorXd ub = scored.scored_rows(U.col(columns[b]));
    const double energy = ua.squaredNorm();
    return energy > 0.0 ? ua.dot(ub) / energy : 0.0;
  }
  // U with input b replaced by its own part u_b − β·u_a.
  Eigen::MatrixXd own_part(const Eigen::MatrixXd& U, const std::vector<int>& columns) const {
    Eigen::MatrixXd out = U;
    out.col(columns[b]) -= beta * U.col(columns[a]);
    return out;
  }

  std::size_t a;  // the input that keeps its movement (position in `inputs`)
  std::size_t b;  // the input replaced by its own part
  double beta;
  Eigen::MatrixXd U_own;
  std::vector<int> inputs;
  double T_min;
  double max_delay_min;
  SampleLayout layout;
  mutable std::once_flag built;
  mutable std::optional<ArxBasis> basis;  // on U_own (it keeps a reference to it)
};

namespace {

// Element g's response to u, each segment from rest.
Eigen::VectorXd response_of(const ElementModel& g, const Eigen::VectorXd& u, double T_min,
                            const SampleLayout& layout) {
  Eigen::VectorXd out(u.size());
  simulate_segments(discretise(g, T_min), {u.data(), static_cast<std::size_t>(u.size())},
                    {out.data(), static_cast<std::size_t>(out.size())}, layout.segments);
  return out;
}

// What the elements of `from` other than a and b leave of row.y: the pair's part of the output.
Eigen::VectorXd pair_part(const RowProblem& row, const std::vector<ElementModel>& from,
                          std::size_t a, std::size_t b) {
  Eigen::VectorXd z = row.y;
  for (std::size_t e = 0; e < from.size(); ++e) {
    if (e == a || e == b) continue;
    z -= response_of(from[e], row.U.col(row.inputs[e]), row.T_min, row.layout);
  }
  return z;
}

// One element on input column `column` of U fitted alone to z from grid element `index`
// with gain `gain`.
ElementModel fit_one(const Eigen::MatrixXd& U, int column, const Eigen::VectorXd& z,
                     const ResponseBank& bank, int index, double gain, const RowProblem& row) {
  ElementModel g = bank.grid()[static_cast<std::size_t>(index)];
  g.gain = gain;
  return fit_miso(U, z, {column}, {g}, row.T_min, row.bounds, row.max_iterations, row.layout,
                  Eigen::MatrixXd(z.size(), 0), LmOptions{}.cost_tolerance, MisoUncertainty::none)
      .elements.front()
      .value;
}

}  // namespace

OwnPartStarts::OwnPartStarts(const Eigen::MatrixXd& U, const std::vector<int>& inputs,
                             std::size_t a, std::size_t b, double T_min, double max_delay_min,
                             const SampleLayout& layout) {
  sides_[0] = std::make_unique<const Side>(U, inputs, a, b, T_min, max_delay_min, layout);
  sides_[1] = std::make_unique<const Side>(U, inputs, b, a, T_min, max_delay_min, layout);
}

OwnPartStarts::~OwnPartStarts() = default;

std::vector<std::vector<ElementModel>> OwnPartStarts::starts(
    const RowProblem& row, const ResponseBank& bank, const std::vector<ElementModel>& from) const {
  return {start(*sides_[0], row, bank, from), start(*sides_[1], row, bank, from)};
}

std::vector<ElementModel> OwnPartStarts::exchanged(std::vector<ElementModel> from) const {
  const Side& side = *sides_[0];
  if (side.beta == 0.0) return from;
  ElementModel a = from[side.b], b = from[side.a];
  a.gain = side.beta * from[side.b].gain;
  b.gain = from[side.a].gain / side.beta;
  from[side.a] = a;
  from[side.b] = b;
  return from;
}

std::vector<ElementModel> OwnPartStarts::start(const Side& side, const RowProblem& row,
                                               const ResponseBank& bank,
                                               std::vector<ElementModel> from) const {
  const auto Z = side.arx().contributions(row.y);
  if (!Z) return from;
  const Eigen::VectorXd& w = row.layout.weight;
  const int column_a = row.inputs[side.a], column_b = row.inputs[side.b];
  const auto a = static_cast<Eigen::Index>(side.a), b = static_cast<Eigen::Index>(side.b);
  // b's element: alone on its own part's contribution (the bank's responses are linear in
  // the input, so the own part's are b's less β times a's).
  const Eigen::VectorXd zb = Z->col(b);
  double gain = 0.0;
  int index = bank.choose_own_part(b, a, side.beta, zb.cwiseProduct(w), gain);
  from[side.b] = fit_one(side.U_own, column_b, zb, bank, index, gain, row);
  // a's element: alone on what b's element on the whole u_b and the other elements leave.
  const Eigen::VectorXd za = pair_part(row, from, side.a, side.b) -
                             response_of(from[side.b], row.U.col(column_b), row.T_min, row.layout);
  index = bank.choose_one(a, za.cwiseProduct(w), gain);
  from[side.a] = fit_one(row.U, column_a, za, bank, index, gain, row);
  return from;
}

std::vector<std::vector<ElementModel>> OwnPartStarts::shared(const RowProblem& row,
                                                             std::vector<ElementModel> from) const {
  const Side& side = *sides_[0];
  const auto ua = row.U.col(row.inputs[side.a]), ub = row.U.col(row.inputs[side.b]);
  const Eigen::VectorXd z = pair_part(row, from, side.a, side.b).cwiseProduct(row.layout.weight);
  const bool a_larger =
      std::abs(from[side.a].gain) * ua.norm() >= std::abs(from[side.b].gain) * ub.norm();
  ElementModel unit = from[a_larger ? side.a : side.b];
  unit.gain = 1.0;
  Eigen::MatrixXd Z(z.size(), 2);
  Z.col(0) = response_of(unit, ua, row.T_min, row.layout).cwiseProduct(row.layout.weight);
  Z.col(1) = response_of(unit, ub, row.T_min, row.layout).cwiseProduct(row.layout.weight);
  const Eigen::Vector2d k = Z.colPivHouseholderQr().solve(z);
  from[side.a] = unit;
  from[side.b] = unit;
  std::vector<std::pair<double, double>> splits{{k(0), k(1)}};
  if (side.beta != 0.0) {
    const double combination = k(0) + side.beta * k(1);
    for (const double to_a : {0.25, 0.5, 0.75})
      splits.emplace_back(to_a * combination, (1.0 - to_a) * combination / side.beta);
  }
  std::vector<std::vector<ElementModel>> out;
  for (const auto& [ka, kb] : splits) {
    from[side.a].gain = ka;
    from[side.b].gain = kb;
    out.push_back(from);
  }
  return out;
}

}  // namespace excite::host
