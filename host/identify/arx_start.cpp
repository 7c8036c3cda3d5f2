// SPDX-License-Identifier: MIT
#include "host/identify/arx_start.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

namespace excite::host {
namespace {

// A relative residual below this is "exact" for the order choice (residual RMS 1e-7 of
// the output's): orders that only fit rounding are not preferred.
constexpr double kExactResidual = 1e-14;

// Singular values of R below this fraction of the largest (unit-norm columns) are taken
// as rank deficiency (columns the data do not distinguish).
constexpr double kRankThreshold = 1e-11;

// A parameter direction whose coefficient's standard error exceeds this fraction of ‖y‖
// is not determined by the data (dropped from the ARX solution).
constexpr double kMaxDirectionError = 0.1;

// Column norm, or 1 for an all-zero column.
double norm_or_one(double n) {
  return n == 0.0 ? 1.0 : n;
}

}  // namespace

ArxBasis::ArxBasis(const Eigen::MatrixXd& U, std::vector<int> inputs, double T_min,
                   double max_delay_min, const SampleLayout& layout)
    : U_(U),
      inputs_(std::move(inputs)),
      N_(U.rows()),
      segments_(layout.segments),
      m_(static_cast<Eigen::Index>(inputs_.size())),
      nb_(static_cast<Eigen::Index>(std::ceil(max_delay_min / T_min)) + 3) {
  const Eigen::Index ub = m_ * nb_;
  const Eigen::Index na_max = 2 * m_;
  // An equation row needs its own output and its output lags 1 … na_max (those inside its
  // segment; before it the plant is at rest) to be scored.
  use_ = layout.weight;
  for (const Segment& s : segments_) {
    for (Eigen::Index k = s.begin; k < s.end; ++k) {
      for (Eigen::Index l = 1; l <= na_max && k - l >= s.begin; ++l) {
        if (layout.weight(k - l) == 0.0) use_(k) = 0.0;
      }
    }
  }
  used_ = static_cast<Eigen::Index>(use_.sum());
  if (m_ == 0 || used_ < 2 * (ub + na_max + 1)) return;
  // Φ_u: input lags 0 … nb − 1 from rest in each segment, unit-norm columns.
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(N_, ub);
  scale_.resize(ub);
  for (Eigen::Index e = 0; e < m_; ++e) {
    const Eigen::VectorXd u = U_.col(inputs_[static_cast<std::size_t>(e)]);
    for (Eigen::Index lag = 0; lag < nb_; ++lag) {
      add_lagged(phi.col(e * nb_ + lag), u, lag, 1.0, segments_);
      phi.col(e * nb_ + lag).array() *= use_.array();
      scale_(e * nb_ + lag) = norm_or_one(phi.col(e * nb_ + lag).norm());
    }
  }
  phi = phi * scale_.cwiseInverse().asDiagonal();
  qr_.compute(phi);
  usable_ = true;
}

std::optional<Eigen::MatrixXd> ArxBasis::contributions(const Eigen::VectorXd& y) const {
  const Eigen::Index ub = m_ * nb_;
  const Eigen::Index na_max = 2 * m_;
  const Eigen::Index P = ub + na_max;
  if (!usable_ || y.size() != N_ || y.cwiseProduct(use_).squaredNorm() == 0.0) {
    return std::nullopt;
  }

  // The output's columns [−y(k − 1) … −y(k − na_max), y], unit norm, projected by Φ_u's Q:
  // R of [Φ_u Φ_y y] = [R_uu  (Qᵀ C)_top ; 0  R of (Qᵀ C)_rest].
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(N_, na_max + 1);
  for (Eigen::Index l = 1; l <= na_max; ++l) add_lagged(C.col(l - 1), y, l, -1.0, segments_);
  C.col(na_max) = y;
  C.array().colwise() *= use_.array();
  Eigen::VectorXd scale(P + 1);
  scale.head(ub) = scale_;
  for (Eigen::Index col = 0; col <= na_max; ++col) {
    scale(ub + col) = norm_or_one(C.col(col).norm());
  }
  C = C * scale.tail(na_max + 1).cwiseInverse().asDiagonal();
  C.applyOnTheLeft(qr_.householderQ().adjoint());
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(P + 1, P + 1);
  R.topLeftCorner(ub, ub) = qr_.matrixQR().topLeftCorner(ub, ub).triangularView<Eigen::Upper>();
  R.topRightCorner(ub, na_max + 1) = C.topRows(ub);
  const Eigen::HouseholderQR<Eigen::MatrixXd> rest(C.bottomRows(N_ - ub));
  R.bottomRightCorner(na_max + 1, na_max + 1) =
      rest.matrixQR().topRows(na_max + 1).triangularView<Eigen::Upper>();

  // Residual of the model with the first c columns: Σ_{l ≥ c} r_l², r = the y column of R
  // (‖y‖ = 1 after scaling).
  Eigen::VectorXd tail2(P + 2);
  tail2(P + 1) = 0.0;
  for (Eigen::Index l = P; l >= 0; --l) tail2(l) = tail2(l + 1) + R(l, P) * R(l, P);
  Eigen::Index na = 0;
  double best = std::numeric_limits<double>::infinity();
  const double log_n = std::log(static_cast<double>(used_));
  for (Eigen::Index order = 0; order <= na_max; ++order) {
    const double rel = std::max(tail2(ub + order), kExactResidual);
    const double bic =
        static_cast<double>(used_) * std::log(rel) + static_cast<double>(ub + order) * log_n;
    if (bic < best) {
      best = bic;
      na = order;
    }
  }
  const Eigen::Index c = ub + na;
  // θ for the first c columns by a truncated SVD of R (c × c: independent of N). A
  // direction v_k of the parameters is kept only when the data determine it: its singular
  // value is not rank deficiency (kRankThreshold, e.g. a multisine with fewer lines than
  // lags: B_i is then free off the excited lines, but B_i u_i is not) and its coefficient's
  // standard error σ̂/s_k is below kMaxDirectionError of ‖y‖ (scaled units). Under noise, a
  // weakly excited direction would otherwise be fitted to the noise with a huge coefficient
  // that the elements' parts cancel in their sum but not one by one (the row's split
  // between elements would be meaningless and diverge).
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(R.topLeftCorner(c, c),
                                           Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double sigma =
      std::sqrt(tail2(c) / static_cast<double>(std::max<Eigen::Index>(used_ - c, 1)));
  const double floor_sv = std::max(kRankThreshold * sv(0), sigma / kMaxDirectionError);
  const Eigen::VectorXd proj = svd.matrixU().transpose() * R.col(P).head(c);
  Eigen::VectorXd theta_scaled = Eigen::VectorXd::Zero(c);
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    if (sv(k) > floor_sv) theta_scaled += svd.matrixV().col(k) * (proj(k) / sv(k));
  }
  const Eigen::VectorXd theta = (theta_scaled * scale(P)).cwiseQuotient(scale.head(c));
  const Eigen::VectorXd a = theta.tail(na);

  Eigen::MatrixXd Z(N_, m_);
  for (Eigen::Index e = 0; e < m_; ++e) {
    const auto u = U_.col(inputs_[static_cast<std::size_t>(e)]);
    const Eigen::VectorXd b = theta.segment(e * nb_, nb_);
    for (const Segment& s : segments_) {  // each segment from rest
      for (Eigen::Index k = s.begin; k < s.end; ++k) {
        const Eigen::Index since = k - s.begin;
        double v = 0.0;
        for (Eigen::Index lag = 0; lag < nb_ && lag <= since; ++lag) v += b(lag) * u(k - lag);
        for (Eigen::Index l = 1; l <= na && l <= since; ++l) v -= a(l - 1) * Z(k - l, e);
        Z(k, e) = v;
      }
    }
  }
  if (!Z.allFinite() || Z.cwiseAbs().maxCoeff() > 1e6 * y.cwiseAbs().maxCoeff()) {
    return std::nullopt;  // A unstable: the contributions diverge
  }
  return Z;
}

}  // namespace excite::host
