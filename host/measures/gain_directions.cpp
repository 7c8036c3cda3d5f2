// SPDX-License-Identifier: MIT
#include "host/measures/gain_directions.hpp"

#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace excite::host {
namespace {

// Smallest singular value within rounding of zero, relative to the largest.
bool rank_deficient(const GainAnalysis& a) {
  const double sigma_max = a.singular_values(0);
  const double tolerance = sigma_max * 1e-12 * static_cast<double>(a.gain.rows() + a.gain.cols());
  return sigma_max == 0.0 || a.singular_values(a.singular_values.size() - 1) <= tolerance;
}

}  // namespace

std::vector<int> GainAnalysis::weak_directions(double xi_threshold) const {
  std::vector<int> weak;
  for (Eigen::Index i = 0; i < xi.size(); ++i) {
    if (xi(i) >= xi_threshold) weak.push_back(static_cast<int>(i));
  }
  return weak;
}

GainAnalysis analyse_gain(const Eigen::MatrixXd& gain) {
  if (gain.size() == 0)
    throw std::invalid_argument("gain matrix: empty, expected outputs × inputs");
  for (Eigen::Index r = 0; r < gain.rows(); ++r) {
    for (Eigen::Index c = 0; c < gain.cols(); ++c) {
      if (!std::isfinite(gain(r, c))) {
        std::ostringstream msg;
        msg << "gain[" << r << "][" << c << "] = " << gain(r, c) << ", expected a finite number";
        throw std::invalid_argument(msg.str());
      }
    }
  }

  Eigen::JacobiSVD<Eigen::MatrixXd> svd(gain, Eigen::ComputeThinU | Eigen::ComputeThinV);
  GainAnalysis a;
  a.gain = gain;
  a.singular_values = svd.singularValues();
  a.output_directions = svd.matrixU();
  a.input_directions = svd.matrixV();
  for (Eigen::Index i = 0; i < a.singular_values.size(); ++i) {
    Eigen::Index largest = 0;
    a.output_directions.col(i).cwiseAbs().maxCoeff(&largest);
    if (a.output_directions(largest, i) < 0.0) {
      a.output_directions.col(i) *= -1.0;
      a.input_directions.col(i) *= -1.0;
    }
  }

  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double sigma_max = a.singular_values(0);
  a.xi = a.singular_values.unaryExpr([&](double s) { return s > 0.0 ? sigma_max / s : kInf; });
  a.condition_number = a.xi(a.xi.size() - 1);
  if (rank_deficient(a)) {
    a.rga = Eigen::MatrixXd::Constant(gain.rows(), gain.cols(),
                                      std::numeric_limits<double>::quiet_NaN());
  } else {
    const Eigen::MatrixXd pseudo_inverse = a.input_directions *
                                           a.singular_values.cwiseInverse().asDiagonal() *
                                           a.output_directions.transpose();
    a.rga = gain.cwiseProduct(pseudo_inverse.transpose());
  }
  return a;
}

void require_full_rank(const GainAnalysis& a) {
  if (rank_deficient(a)) {
    std::ostringstream msg;
    msg << "gain matrix: singular (smallest singular value "
        << a.singular_values(a.singular_values.size() - 1)
        << "), expected full rank so that every gain direction can be reached";
    throw std::invalid_argument(msg.str());
  }
}

std::vector<OutputExcursion> static_output_excursions(const Eigen::MatrixXd& gain,
                                                      const Eigen::MatrixXd& table) {
  if (table.cols() != gain.cols()) {
    std::ostringstream msg;
    msg << "static_output_excursions: table has " << table.cols() << " channels, the gain matrix "
        << gain.cols() << " inputs";
    throw std::invalid_argument(msg.str());
  }
  const Eigen::MatrixXd outputs = table * gain.transpose();
  std::vector<OutputExcursion> excursions(static_cast<std::size_t>(gain.rows()));
  for (Eigen::Index r = 0; r < gain.rows(); ++r) {
    excursions[static_cast<std::size_t>(r)] = {outputs.col(r).minCoeff(),
                                               outputs.col(r).maxCoeff()};
  }
  return excursions;
}

}  // namespace excite::host
