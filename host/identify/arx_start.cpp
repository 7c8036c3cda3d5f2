// SPDX-License-Identifier: MIT
#include "host/identify/arx_start.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace excite::host {
namespace {

// A relative residual below this is "exact" for the order choice (residual RMS 1e-7 of
// the output's): orders that only fit rounding are not preferred.
constexpr double kExactResidual = 1e-14;

// Diagonal entries of R below this fraction of the largest (unit-norm columns) are taken
// as rank deficiency (columns the data do not distinguish).
constexpr double kRankThreshold = 1e-11;

}  // namespace

std::optional<Eigen::MatrixXd> arx_contributions(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                                                 const std::vector<int>& inputs, double T_min,
                                                 double max_delay_min) {
  const Eigen::Index N = y.size();
  const auto m = static_cast<Eigen::Index>(inputs.size());
  const auto nb = static_cast<Eigen::Index>(std::ceil(max_delay_min / T_min)) + 3;
  const Eigen::Index na_max = 2 * m;
  const Eigen::Index ub = m * nb;  // columns of the input lags
  const Eigen::Index P = ub + na_max;
  if (m == 0 || N < 2 * (P + 1) || y.squaredNorm() == 0.0) return std::nullopt;

  // [Φ y]: input lags, then −y(k − l), l = 1 … na_max, then y; from rest (zeros before 0);
  // every column scaled to unit norm (the rank test is about directions, not units; an
  // all-zero column keeps scale 1). Norms from prefix sums of squares.
  const auto prefix2 = [N](const auto& x) {
    Eigen::VectorXd c(N + 1);
    c(0) = 0.0;
    for (Eigen::Index k = 0; k < N; ++k) c(k + 1) = c(k) + x(k) * x(k);
    return c;
  };
  Eigen::VectorXd scale(P + 1);
  for (Eigen::Index e = 0; e < m; ++e) {
    const Eigen::VectorXd c = prefix2(U.col(inputs[static_cast<std::size_t>(e)]));
    for (Eigen::Index lag = 0; lag < nb; ++lag) scale(e * nb + lag) = std::sqrt(c(N - lag));
  }
  const Eigen::VectorXd y2s = prefix2(y);
  for (Eigen::Index l = 1; l <= na_max; ++l) scale(ub + l - 1) = std::sqrt(y2s(N - l));
  scale(P) = std::sqrt(y2s(N));
  for (Eigen::Index col = 0; col <= P; ++col) {
    if (scale(col) == 0.0) scale(col) = 1.0;
  }

  // R of [Φ y] by a QR per chunk of rows stacked under the R so far (tall-skinny QR): the
  // same R as one QR of all N rows, in cache-sized pieces, so the cost is N·P² with a
  // constant that does not grow with N.
  const Eigen::Index chunk = std::max<Eigen::Index>(2048, 2 * (P + 1));
  Eigen::MatrixXd W(P + 1 + chunk, P + 1);
  Eigen::Index top = 0;  // rows of R at the top of W
  for (Eigen::Index k0 = 0; k0 < N; k0 += chunk) {
    const Eigen::Index C = std::min(chunk, N - k0);
    W.middleRows(top, C).setZero();
    for (Eigen::Index r = 0; r < C; ++r) {
      const Eigen::Index k = k0 + r;
      const Eigen::Index row = top + r;
      for (Eigen::Index e = 0; e < m; ++e) {
        const auto u = U.col(inputs[static_cast<std::size_t>(e)]);
        for (Eigen::Index lag = 0; lag < nb && lag <= k; ++lag) {
          W(row, e * nb + lag) = u(k - lag) / scale(e * nb + lag);
        }
      }
      for (Eigen::Index l = 1; l <= na_max && l <= k; ++l) {
        W(row, ub + l - 1) = -y(k - l) / scale(ub + l - 1);
      }
      W(row, P) = y(k) / scale(P);
    }
    const Eigen::Index rows = top + C;
    Eigen::Ref<Eigen::MatrixXd> stacked = W.topRows(rows);
    const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(stacked);  // in place
    top = std::min(rows, P + 1);
    W.topRows(top).triangularView<Eigen::StrictlyLower>().setZero();
  }
  const auto R = W.topRows(P + 1);
  const double y2 = 1.0;  // ‖y‖² after scaling

  // Residual of the model with the first c columns: Σ_{l ≥ c} r_l², r = the y column of R.
  Eigen::VectorXd tail2(P + 2);
  tail2(P + 1) = 0.0;
  for (Eigen::Index l = P; l >= 0; --l) tail2(l) = tail2(l + 1) + R(l, P) * R(l, P);
  Eigen::Index na = 0;
  double best = std::numeric_limits<double>::infinity();
  const double log_n = std::log(static_cast<double>(N));
  for (Eigen::Index order = 0; order <= na_max; ++order) {
    const double rel = std::max(tail2(ub + order) / y2, kExactResidual);
    const double bic =
        static_cast<double>(N) * std::log(rel) + static_cast<double>(ub + order) * log_n;
    if (bic < best) {
      best = bic;
      na = order;
    }
  }
  const Eigen::Index c = ub + na;
  // θ for the first c columns; the minimum-norm solution when the input lags are rank
  // deficient (a multisine with fewer lines than lags: B_i is then free off the excited
  // lines, but B_i u_i, the element's part of the output, is not).
  const Eigen::MatrixXd Rc = R.topLeftCorner(c, c);
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(kRankThreshold);
  cod.compute(Rc);
  const Eigen::VectorXd theta =
      (cod.solve(R.col(P).head(c)) * scale(P)).cwiseQuotient(scale.head(c));
  const Eigen::VectorXd a = theta.tail(na);

  Eigen::MatrixXd Z(N, m);
  for (Eigen::Index e = 0; e < m; ++e) {
    const auto u = U.col(inputs[static_cast<std::size_t>(e)]);
    const Eigen::VectorXd b = theta.segment(e * nb, nb);
    for (Eigen::Index k = 0; k < N; ++k) {
      double v = 0.0;
      for (Eigen::Index lag = 0; lag < nb && lag <= k; ++lag) v += b(lag) * u(k - lag);
      for (Eigen::Index l = 1; l <= na && l <= k; ++l) v -= a(l - 1) * Z(k - l, e);
      Z(k, e) = v;
    }
  }
  if (!Z.allFinite() || Z.cwiseAbs().maxCoeff() > 1e6 * y.cwiseAbs().maxCoeff()) {
    return std::nullopt;  // A unstable: the contributions diverge
  }
  return Z;
}

}  // namespace excite::host
