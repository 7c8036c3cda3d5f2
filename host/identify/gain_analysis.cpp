// SPDX-License-Identifier: MIT
#include "host/identify/gain_analysis.hpp"

#include <limits>
#include <stdexcept>

namespace excite::host {

GainAnalysis analyse_gain(const Eigen::MatrixXd& G) {
  if (G.size() == 0) throw std::invalid_argument("analyse_gain: the gain matrix is empty");
  if (!G.allFinite()) {
    throw std::invalid_argument("analyse_gain: the gain matrix has NaN or inf entries");
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  GainAnalysis a;
  a.gain = G;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeThinU | Eigen::ComputeThinV);
  a.singular_values = svd.singularValues();
  a.output_directions = svd.matrixU();
  a.input_directions = svd.matrixV();
  const Eigen::Index r = a.singular_values.size();
  const double s1 = a.singular_values(0);
  a.xi.resize(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    a.xi(i) = a.singular_values(i) > 0.0 ? s1 / a.singular_values(i) : kInf;
  }
  a.condition_number = a.xi(r - 1);
  // RGA = G ∘ (G⁺)ᵀ, with G⁺ from the SVD; undefined (NaN) when G is rank deficient.
  const double tol = s1 * static_cast<double>(std::max(G.rows(), G.cols())) *
                     std::numeric_limits<double>::epsilon();
  if (s1 == 0.0 || a.singular_values(r - 1) <= tol) {
    a.rga = Eigen::MatrixXd::Constant(G.rows(), G.cols(), std::numeric_limits<double>::quiet_NaN());
  } else {
    const Eigen::MatrixXd pinv = a.input_directions *
                                 a.singular_values.cwiseInverse().asDiagonal() *
                                 a.output_directions.transpose();
    a.rga = G.cwiseProduct(pinv.transpose());
  }
  return a;
}

}  // namespace excite::host
