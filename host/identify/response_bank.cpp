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
  const Eigen::MatrixXf& R = responses_[static_cast<std::size_t>(e)];
  const Eigen::VectorXf proj = R.transpose() * z.cast<float>();
  const Eigen::VectorXf& n2 = norms2_[static_cast<std::size_t>(e)];
  Eigen::Index best = 0;
  float best_score = -1.0F;
  for (Eigen::Index g = 0; g < proj.size(); ++g) {
    const float score = n2(g) > 0.0F ? proj(g) * proj(g) / n2(g) : 0.0F;
    if (score > best_score) {
      best_score = score;
      best = g;
    }
  }
  gain = n2(best) > 0.0F ? static_cast<double>(proj(best) / n2(best)) : 0.0;
  return static_cast<int>(best);
}

ResponseBank::Choice ResponseBank::choose(const Eigen::VectorXd& y) const {
  const auto m = static_cast<Eigen::Index>(responses_.size());
  const Eigen::Index N = y.size();
  Choice c;
  c.grid_index.assign(static_cast<std::size_t>(m), -1);
  c.gain = Eigen::VectorXd::Zero(m);
  Eigen::MatrixXd selected = Eigen::MatrixXd::Zero(N, m);
  Eigen::VectorXd r = y;
  for (int sweep = 0; sweep < 6; ++sweep) {
    bool changed = false;
    for (Eigen::Index i = 0; i < m; ++i) {
      // Residual without element i; the best grid response by the 1-D least-squares gain.
      const Eigen::VectorXf ri = (r + c.gain(i) * selected.col(i)).cast<float>();
      const Eigen::VectorXf proj = responses_[static_cast<std::size_t>(i)].transpose() * ri;
      const Eigen::VectorXf& n2 = norms2_[static_cast<std::size_t>(i)];
      Eigen::Index best = 0;
      float best_score = -1.0F;
      for (Eigen::Index g = 0; g < proj.size(); ++g) {
        const float score = n2(g) > 0.0F ? proj(g) * proj(g) / n2(g) : 0.0F;
        if (score > best_score) {
          best_score = score;
          best = g;
        }
      }
      if (best != c.grid_index[static_cast<std::size_t>(i)]) {
        changed = true;
        c.grid_index[static_cast<std::size_t>(i)] = static_cast<int>(best);
        selected.col(i) = responses_[static_cast<std::size_t>(i)].col(best).cast<double>();
      }
      // Gains of all chosen elements jointly (columns not yet chosen are zero: gain 0).
      c.gain = selected.colPivHouseholderQr().solve(y);
      r = y - selected * c.gain;
    }
    if (!changed) break;
  }
  return c;
}

}  // namespace excite::host
