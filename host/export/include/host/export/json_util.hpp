// SPDX-License-Identifier: MIT
#pragma once
// Eigen values as JSON: matrices as arrays of rows; NaN as null.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cmath>

namespace excite::host {

inline nlohmann::json to_json(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

inline nlohmann::json to_json(const Eigen::VectorXd& v) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(to_json(v(i)));
  return out;
}

inline nlohmann::json rows_to_json(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    out.push_back(to_json(Eigen::VectorXd(m.row(r).transpose())));
  return out;
}

inline nlohmann::json columns_to_json(const Eigen::MatrixXd& m) {
  return rows_to_json(m.transpose());
}

}  // namespace excite::host
