// SPDX-License-Identifier: MIT
#include "host/identify/balance.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace excite::host {
namespace {

void check_outputs(const Eigen::MatrixXd& Y, const char* who) {
  if (Y.rows() < 2 || Y.cols() < 1) {
    throw std::invalid_argument(std::string(who) + ": Y is " + std::to_string(Y.rows()) + "×" +
                                std::to_string(Y.cols()) +
                                ", expected N × p with N ≥ 2 samples and p ≥ 1 outputs");
  }
  if (!Y.allFinite()) throw std::invalid_argument(std::string(who) + ": Y contains NaN or inf");
}

Eigen::VectorXd column_std(const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd centred = X.rowwise() - X.colwise().mean();
  return (centred.colwise().squaredNorm().array() / static_cast<double>(X.rows() - 1))
      .sqrt()
      .transpose();
}

}  // namespace

DirectionalBalance directional_balance(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& W) {
  check_outputs(Y, "directional_balance");
  if (W.rows() != Y.cols() || W.cols() < 1 || !W.allFinite()) {
    throw std::invalid_argument("directional_balance: W is " + std::to_string(W.rows()) + "×" +
                                std::to_string(W.cols()) + ", expected " +
                                std::to_string(Y.cols()) +
                                " rows (one per output), finite, at least one direction");
  }
  DirectionalBalance b;
  b.projections = Y * W;
  b.std_dev = column_std(b.projections);
  const double hi = b.std_dev.maxCoeff();
  if (hi == 0.0) {
    throw std::invalid_argument(
        "directional_balance: every projection is constant (the outputs never moved)");
  }
  b.ratio = b.std_dev.minCoeff() / hi;
  return b;
}

double output_correlation_determinant(const Eigen::MatrixXd& Y) {
  check_outputs(Y, "output_correlation_determinant");
  const Eigen::MatrixXd centred = Y.rowwise() - Y.colwise().mean();
  const Eigen::VectorXd norms = centred.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < norms.size(); ++j) {
    if (norms(j) == 0.0) {
      throw std::invalid_argument("output_correlation_determinant: output " +
                                  std::to_string(j + 1) +
                                  " is constant; its correlation is undefined");
    }
  }
  const Eigen::MatrixXd Z = centred * norms.cwiseInverse().asDiagonal();
  return (Z.transpose() * Z).determinant();
}

}  // namespace excite::host
