// SPDX-License-Identifier: MIT
#include "host/identify/response_bank.hpp"

#include <algorithm>
#include <cmath>

namespace excite::host {

ResponseBank::ResponseBank(const Eigen::MatrixXd& U, const std::vector<int>& inputs, double T_min,
                           const GridSpec& spec, const SampleLayout& layout) {
  const Eigen::Index N = U.rows();
  const double delay_step = std::max(T_min, spec.max_delay_min / 10.0);
  const double tau_top =
      std::max(T_min, std::min(spec.max_time_constant_min, static_cast<double>(N) * T_min / 8.0));
  for (double td = 0.0; td <= spec.max_delay_min + 1e-9 * delay_step; td += delay_step) {
    for (double tau = T_min / 2.0; tau <= tau_top * (1.0 + 1e-9); tau *= 2.0) {
      grid_.push_back(ElementModel{1.0, std::min(td, spec.max_delay_min), tau, tau / 4.0});
    }
  }
  const auto G = static_cast<Eigen::Index>(grid_.size());
  std::vector<sim::DiscreteTerm> discrete;
  discrete.reserve(grid_.size());
  for (const auto& g : grid_) discrete.push_back(discretise(g, T_min));

  Eigen::VectorXd buffer(N);
  for (const int i : inputs) {
    Eigen::MatrixXf R(N, G);
    for (Eigen::Index g = 0; g < G; ++g) {
      simulate_segments(discrete[static_cast<std::size_t>(g)],
                        {U.col(i).data(), static_cast<std::size_t>(N)},
                        {buffer.data(), static_cast<std::size_t>(N)}, layout.segments);
      R.col(g) = buffer.cwiseProduct(layout.weight).cast<float>();
    }
    norms2_.push_back(R.colwise().squaredNorm().transpose());
    responses_.push_back(std::move(R));
  }
}

int ResponseBank::choose_one(Eigen::Index e, const Eigen::VectorXd& z, double& gain) const {
  const Best b = best_response(e, z);
  gain = b.norm2 > 0.0F ? static_cast<double>(b.projection / b.norm2) : 0.0;
  return static_cast<int>(b.index);
}

namespace {

// Of responses with projections zᵀr `proj` and squared norms ‖z‖² `n2`, the one whose 1-D
// least-squares gain reduces ‖r‖² most: the largest (zᵀr)²/‖z‖².
Eigen::Index best_column(const Eigen::VectorXf& proj, const Eigen::VectorXf& n2) {
  Eigen::Index best = 0;
  float best_score = -1.0F;
  for (Eigen::Index g = 0; g < proj.size(); ++g) {
    const float score = n2(g) > 0.0F ? proj(g) * proj(g) / n2(g) : 0.0F;
    if (score > best_score) {
      best_score = score;
      best = g;
    }
  }
  return best;
}

}  // namespace

ResponseBank::Best ResponseBank::best_response(Eigen::Index i, const Eigen::VectorXd& r) const {
  const Eigen::VectorXf proj =
      responses_[static_cast<std::size_t>(i)].transpose() * r.cast<float>();
  const Eigen::VectorXf& n2 = norms2_[static_cast<std::size_t>(i)];
  const Eigen::Index best = best_column(proj, n2);
  return {best, proj(best), n2(best)};
}

std::vector<ElementModel> ResponseBank::elements(const Choice& choice) const {
  std::vector<ElementModel> out;
  for (std::size_t e = 0; e < choice.grid_index.size(); ++e) {
    ElementModel g = grid_[static_cast<std::size_t>(choice.grid_index[e])];
    g.gain = choice.gain(static_cast<Eigen::Index>(e));
    out.push_back(g);
  }
  return out;
}

ResponseBank::Choice ResponseBank::choose(const Eigen::VectorXd& y) const {
  return choose_shared(y, {});
}

ResponseBank::Choice ResponseBank::choose_shared(const Eigen::VectorXd& y,
                                                 const std::vector<Eigen::Index>& group) const {
  const auto m = static_cast<Eigen::Index>(responses_.size());
  const Eigen::Index N = y.size();
  const auto in_group = [&](Eigen::Index i) {
    return std::find(group.begin(), group.end(), i) != group.end();
  };
  Choice c;
  c.grid_index.assign(static_cast<std::size_t>(m), -1);
  c.gain = Eigen::VectorXd::Zero(m);
  Eigen::MatrixXd selected = Eigen::MatrixXd::Zero(N, m);
  Eigen::VectorXd r = y;
  const auto G = static_cast<Eigen::Index>(grid_.size());
  const auto g = static_cast<Eigen::Index>(group.size());
  for (int sweep = 0; sweep < 6; ++sweep) {
    bool changed = false;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (in_group(i)) continue;
      // Residual without element i; the best grid response by the 1-D least-squares gain.
      const Eigen::Index best = best_response(i, r + c.gain(i) * selected.col(i)).index;
      if (best != c.grid_index[static_cast<std::size_t>(i)]) {
        changed = true;
        c.grid_index[static_cast<std::size_t>(i)] = static_cast<int>(best);
        selected.col(i) = responses_[static_cast<std::size_t>(i)].col(best).cast<double>();
      }
      // Gains of all chosen elements jointly (columns not yet chosen are zero: gain 0).
      c.gain = selected.colPivHouseholderQr().solve(y);
      r = y - selected * c.gain;
    }
    if (group.empty()) {
      if (!changed) break;
      continue;
    }
    // The group: the grid element whose responses, one per group input, least-squares fit
    // the residual without the group best.
    Eigen::VectorXd rg = r;
    for (const Eigen::Index i : group) rg += c.gain(i) * selected.col(i);
    Eigen::Index best = 0;
    double best_score = -1.0;
    Eigen::MatrixXd Z(N, g);
    for (Eigen::Index q = 0; q < G; ++q) {
      for (Eigen::Index a = 0; a < g; ++a) {
        Z.col(a) = responses_[static_cast<std::size_t>(group[static_cast<std::size_t>(a)])]
                       .col(q)
                       .cast<double>();
      }
      const Eigen::VectorXd k = Z.colPivHouseholderQr().solve(rg);
      const double score = (Z * k).squaredNorm();  // the reduction of ‖rg‖²
      if (score > best_score) {
        best_score = score;
        best = q;
      }
    }
    for (const Eigen::Index i : group) {
      changed = changed || best != c.grid_index[static_cast<std::size_t>(i)];
      c.grid_index[static_cast<std::size_t>(i)] = static_cast<int>(best);
      selected.col(i) = responses_[static_cast<std::size_t>(i)].col(best).cast<double>();
    }
    c.gain = selected.colPivHouseholderQr().solve(y);
    r = y - selected * c.gain;
    if (!changed) break;
  }
  return c;
}

ResponseBank::Choice ResponseBank::choose_pair(const Eigen::VectorXd& y, Eigen::Index a,
                                               Eigen::Index b) const {
  Choice c = choose(y);
  const auto m = static_cast<Eigen::Index>(responses_.size());
  Eigen::MatrixXd selected(y.size(), m);
  for (Eigen::Index i = 0; i < m; ++i) {
    selected.col(i) = responses_[static_cast<std::size_t>(i)]
                          .col(c.grid_index[static_cast<std::size_t>(i)])
                          .cast<double>();
  }
  const Eigen::VectorXf r =
      (y - selected * c.gain + c.gain(a) * selected.col(a) + c.gain(b) * selected.col(b))
          .cast<float>();
  const Eigen::MatrixXf& Ra = responses_[static_cast<std::size_t>(a)];
  const Eigen::MatrixXf& Rb = responses_[static_cast<std::size_t>(b)];
  const Eigen::MatrixXf cross = Ra.transpose() * Rb;  // z_a(p)ᵀ z_b(q)
  const Eigen::VectorXf ra = Ra.transpose() * r, rb = Rb.transpose() * r;
  const Eigen::VectorXf& na = norms2_[static_cast<std::size_t>(a)];
  const Eigen::VectorXf& nb = norms2_[static_cast<std::size_t>(b)];
  double best_score = -1.0;
  Eigen::Index best_p = 0, best_q = 0;
  for (Eigen::Index q = 0; q < Rb.cols(); ++q) {
    for (Eigen::Index p = 0; p < Ra.cols(); ++p) {
      // The reduction of ‖r‖² by both responses' least-squares gains: gᵀ A⁻¹ g for the 2 × 2
      // Gram matrix A and g = (z_aᵀ r, z_bᵀ r), in double (A is near singular by design).
      const double A11 = na(p), A22 = nb(q), A12 = cross(p, q);
      const double det = A11 * A22 - A12 * A12;
      if (!(det > 1e-12 * A11 * A22)) continue;
      const double g1 = ra(p), g2 = rb(q);
      const double score = (A22 * g1 * g1 - 2.0 * A12 * g1 * g2 + A11 * g2 * g2) / det;
      if (score > best_score) {
        best_score = score;
        best_p = p;
        best_q = q;
      }
    }
  }
  c.grid_index[static_cast<std::size_t>(a)] = static_cast<int>(best_p);
  c.grid_index[static_cast<std::size_t>(b)] = static_cast<int>(best_q);
  selected.col(a) = Ra.col(best_p).cast<double>();
  selected.col(b) = Rb.col(best_q).cast<double>();
  c.gain = selected.colPivHouseholderQr().solve(y);
  return c;
}

int ResponseBank::choose_own_part(Eigen::Index b, Eigen::Index a, double beta,
                                  const Eigen::VectorXd& z, double& gain) const {
  const Eigen::MatrixXf R = responses_[static_cast<std::size_t>(b)] -
                            static_cast<float>(beta) * responses_[static_cast<std::size_t>(a)];
  const Eigen::VectorXf proj = R.transpose() * z.cast<float>();
  const Eigen::VectorXf n2 = R.colwise().squaredNorm().transpose();
  const Eigen::Index best = best_column(proj, n2);
  gain = n2(best) > 0.0F ? static_cast<double>(proj(best) / n2(best)) : 0.0;
  return static_cast<int>(best);
}

}  // namespace excite::host
