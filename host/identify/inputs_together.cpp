// SPDX-License-Identifier: MIT
#include "host/identify/inputs_together.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "host/identify/element.hpp"

namespace excite::host {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

InputSeparation row_separation(const RowProblem& row, const MisoResult& fit) {
  const auto m = static_cast<Eigen::Index>(row.inputs.size());
  const Eigen::Index scored = row.layout.scored();
  Eigen::MatrixXd raw(scored, m), filtered(scored, m);
  Eigen::VectorXd z(row.U.rows());
  bool filtered_known = true;
  for (Eigen::Index e = 0; e < m; ++e) {
    const auto u = row.U.col(row.inputs[static_cast<std::size_t>(e)]);
    raw.col(e) = row.layout.scored_rows(u);
    ElementModel unit = fit.elements[static_cast<std::size_t>(e)].value;
    unit.gain = 1.0;
    try {
      simulate_segments(discretise(unit, row.T_min), {u.data(), static_cast<std::size_t>(u.size())},
                        {z.data(), static_cast<std::size_t>(z.size())}, row.layout.segments);
    } catch (const std::invalid_argument&) {
      filtered_known = false;  // an element the discretisation cannot take: the raw screen
      continue;
    }
    filtered.col(e) = row.layout.scored_rows(z);
  }
  const Eigen::VectorXd norms = filtered.colwise().norm();
  filtered_known = filtered_known && norms.allFinite() && (norms.array() > 0.0).all();
  const InputSeparation as_moved = input_separation(raw);
  return filtered_known ? worse_of(as_moved, input_separation(filtered)) : as_moved;
}

MisoResult profile_doubtful_gains(const RowProblem& row, MisoResult fit,
                                  const InputSeparation& separation) {
  const auto together = [&](int e) { return separation.independent(e) < kCannotSplit; };
  MisoResult profiled = profile_gains(row, std::move(fit), [&](const MisoResult& f, int e) {
    return together(e) || poorly_determined(f.elements[static_cast<std::size_t>(e)]);
  });
  if (separation.independent.size() > 0 && separation.independent.minCoeff() < kCannotSplit)
    own_part_floor(row, profiled);
  return profiled;
}

void own_part_floor(const RowProblem& row, MisoResult& fit) {
  const auto m = static_cast<Eigen::Index>(row.inputs.size());
  if (m < 2 || !fit.gain_covariance.allFinite()) return;
  const Eigen::Index scored = row.layout.scored();
  // The common response: the element whose part of the output is largest.
  Eigen::MatrixXd Z(scored, m);
  Eigen::VectorXd z(row.U.rows());
  const Eigen::Index largest = std::max<Eigen::Index>(largest_response(row, fit), 0);
  ElementModel unit = fit.elements[static_cast<std::size_t>(largest)].value;
  unit.gain = 1.0;
  try {
    const sim::DiscreteTerm g = discretise(unit, row.T_min);
    for (Eigen::Index e = 0; e < m; ++e) {
      const auto u = row.U.col(row.inputs[static_cast<std::size_t>(e)]);
      simulate_segments(g, {u.data(), static_cast<std::size_t>(u.size())},
                        {z.data(), static_cast<std::size_t>(z.size())}, row.layout.segments);
      Z.col(e) = row.layout.scored_rows(z);
    }
  } catch (const std::invalid_argument&) {
    return;
  }
  const double dof = row_dof(row, fit);
  if (!(dof > 0.0)) return;
  const double sigma2 = row_cost(row, fit) / dof;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Z.transpose() * Z);
  if (!(eig.eigenvalues()(0) > 0.0)) return;
  const Eigen::VectorXd d = eig.eigenvectors().col(0);  // the least informed direction
  const double floor = sigma2 / eig.eigenvalues()(0);
  add_gain_variance(fit, d, floor - d.dot(fit.gain_covariance * d));
}

void cover_other_optima(const RowProblem& row, MisoResult& fit, const InputSeparation& separation,
                        const std::vector<RowOptimum>& optima) {
  const auto m = static_cast<Eigen::Index>(row.inputs.size());
  if (optima.size() < 2 || separation.independent.size() != m ||
      !(separation.independent.minCoeff() < kCannotSplit) || !fit.gain_covariance.allFinite())
    return;
  const double dof = row_dof(row, fit);
  if (!(dof > 0.0)) return;
  const double sigma2 = row_cost(row, fit) / dof;
  double least = std::numeric_limits<double>::infinity();
  for (const RowOptimum& o : optima) least = std::min(least, o.sse);
  const Eigen::VectorXd K = gains_of(fit);
  const Eigen::VectorXd se = fit.gain_covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (const RowOptimum& o : optima) {
    const double rise = (o.sse - least) / sigma2;
    if (!(rise <= 1.96 * 1.96) || o.gains.size() != m) continue;
    const Eigen::VectorXd d = o.gains - K;
    // Around the other optimum the set reaches √(1.96² − rise) = 1.96·left of its SEs.
    const double left = std::sqrt(1.0 - rise / (1.96 * 1.96));
    double alpha = 0.0;  // the variance along d that puts each split gain's 1.96 SE that far
    for (Eigen::Index e = 0; e < m; ++e) {
      if (!(separation.independent(e) < kCannotSplit) || d(e) == 0.0) continue;
      const double there = o.se.size() == m && std::isfinite(o.se(e)) ? o.se(e) : se(e);
      const double reach = std::abs(d(e)) / 1.96 + left * there;
      const double need = reach * reach - fit.gain_covariance(e, e);
      alpha = std::max(alpha, need / (d(e) * d(e)));
    }
    add_gain_variance(fit, d, alpha);
  }
}

std::string describe_together(const std::vector<int>& inputs, const InputSeparation& separation) {
  std::string text;
  const Eigen::Index m = separation.independent.size();
  for (Eigen::Index e = 0; e < m; ++e) {
    if (!(separation.independent(e) < kTogether)) continue;
    const std::string name = std::to_string(inputs[static_cast<std::size_t>(e)] + 1);
    const Eigen::VectorXd b = separation.regression.col(e);
    const double largest = b.cwiseAbs().maxCoeff();
    std::string with, combination;
    for (Eigen::Index k = 0; k < m; ++k) {
      if (k == e || !(std::abs(b(k)) >= 0.1 * largest)) continue;
      const std::string other = std::to_string(inputs[static_cast<std::size_t>(k)] + 1);
      with += (with.empty() ? "" : ", ") + ("input " + other);
      combination +=
          (combination.empty() ? "" : ", ") + ("K" + other + " + " + number(b(k)) + "·K" + name);
    }
    text +=
        (text.empty() ? "" : "; ") +
        ("input " + name + " moves with " + with + " (its own part is " +
         number(100.0 * separation.independent(e)) + " % of its movement): the data determine " +
         combination + " and hardly how each splits; move input " + name +
         " on its own, or identify the combination");
  }
  return text;
}

void grade_together(const std::vector<ElementEstimate*>& row, const std::vector<int>& usable,
                    const InputSeparation& separation) {
  for (Eigen::Index e = 0; e < separation.independent.size(); ++e) {
    if (!(separation.independent(e) < kCannotSplit)) continue;
    ElementEstimate& est = *row[static_cast<std::size_t>(usable[static_cast<std::size_t>(e)])];
    if (!est.estimated()) continue;
    if (est.grade < Grade::C) est.grade = Grade::C;
    est.grade_reason +=
        (est.grade_reason.empty() ? "" : "; ") +
        ("input moves with others (own part " + number(100.0 * separation.independent(e)) +
         " %): the split of its gain from theirs rests on the elements' "
         "dynamics alone, at most C");
  }
}

}  // namespace excite::host
