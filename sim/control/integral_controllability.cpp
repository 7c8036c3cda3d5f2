// SPDX-License-Identifier: MIT
#include "sim/control/integral_controllability.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace excite::sim::control {
namespace {

Eigen::MatrixXd principal_submatrix(const Eigen::MatrixXd& g, unsigned mask) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index k = 0; k < g.rows(); ++k) {
    if ((mask >> k) & 1U) rows.push_back(k);
  }
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd sub(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) {
      sub(a, b) = g(rows[static_cast<std::size_t>(a)], rows[static_cast<std::size_t>(b)]);
    }
  }
  return sub;
}

// "1,3" for the mask of rows 0 and 2 (1-based, as an engineer counts MVs and CVs).
std::string indices(unsigned mask) {
  std::string out;
  for (unsigned k = 0; k < 32; ++k) {
    if ((mask >> k) & 1U) out += (out.empty() ? "" : ",") + std::to_string(k + 1);
  }
  return out;
}

// Four significant digits: enough to see a sign and a size.
std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

}  // namespace

std::vector<double> principal_minors(const Eigen::MatrixXd& gain) {
  if (gain.rows() != gain.cols() || gain.rows() < 1 || gain.rows() > 16) {
    throw std::invalid_argument("gain = " + std::to_string(gain.rows()) + "×" +
                                std::to_string(gain.cols()) +
                                ", expected a square matrix of 1 to 16 rows");
  }
  const auto n = static_cast<unsigned>(gain.rows());
  std::vector<double> out;
  for (unsigned mask = 1; mask < (1U << n); ++mask) {
    out.push_back(principal_submatrix(gain, mask).determinant());
  }
  return out;
}

config::Check check_integral_controllability(const Eigen::MatrixXd& model_gain,
                                             const Eigen::MatrixXd& plant_gain,
                                             std::string_view model_name) {
  if (model_gain.rows() != model_gain.cols() || model_gain.rows() != plant_gain.rows() ||
      model_gain.cols() != plant_gain.cols()) {
    return config::Check::valid();
  }
  const std::vector<double> model = principal_minors(model_gain);
  const std::vector<double> plant = principal_minors(plant_gain);
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (plant[i] == 0.0 || model[i] * plant[i] > 0.0) continue;
    const auto mask = static_cast<unsigned>(i + 1);
    return config::Check::invalid(
        "model",
        "\"" + std::string(model_name) + "\" with det G(0)[" + indices(mask) +
            "] = " + short_number(model[i]) + " where the plant's is " + short_number(plant[i]),
        "a model whose principal minors of G(0) all have the plant's signs (this one is not "
        "integrally controllable: under integral action the loop would be unstable)");
  }
  return config::Check::valid();
}

}  // namespace excite::sim::control
