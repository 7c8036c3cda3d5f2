// SPDX-License-Identifier: MIT
#include "host/identify/validate.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::host {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

double fit_percent(const Eigen::VectorXd& y, const Eigen::VectorXd& y_hat) {
  if (y.size() == 0 || y.size() != y_hat.size()) {
    throw std::invalid_argument("fit_percent: y has " + std::to_string(y.size()) +
                                " samples and ŷ " + std::to_string(y_hat.size()) +
                                ", expected the same non-zero length");
  }
  const double spread = (y.array() - y.mean()).matrix().norm();
  if (spread == 0.0 || !y_hat.allFinite()) return kNaN;
  return 100.0 * (1.0 - (y_hat - y).norm() / spread);
}

std::vector<double> fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                        const Eigen::MatrixXd& Y) {
  if (U.cols() != model.inputs || Y.cols() != model.outputs || U.rows() != Y.rows() ||
      U.rows() == 0) {
    throw std::invalid_argument(
        "fit: data U " + std::to_string(U.rows()) + "×" + std::to_string(U.cols()) + ", Y " +
        std::to_string(Y.rows()) + "×" + std::to_string(Y.cols()) + " do not match the model (" +
        std::to_string(model.inputs) + " inputs, " + std::to_string(model.outputs) +
        " outputs), expected N×n and N×p with the same N > 0");
  }
  if (!U.allFinite() || !Y.allFinite()) {
    throw std::invalid_argument("fit: the data contain NaN or inf");
  }
  const Eigen::MatrixXd Y_hat = simulate(model, U);
  std::vector<double> out;
  for (Eigen::Index j = 0; j < Y.cols(); ++j) out.push_back(fit_percent(Y.col(j), Y_hat.col(j)));
  return out;
}

CrossValidation cross_validate(const std::vector<IdentifiedModel>& models,
                               const std::vector<Dataset>& data) {
  if (models.size() != data.size() || models.size() < 2) {
    throw std::invalid_argument("cross_validate: " + std::to_string(models.size()) +
                                " models and " + std::to_string(data.size()) +
                                " data sets, expected one model per data set, at least two");
  }
  const auto R = static_cast<Eigen::Index>(models.size());
  for (std::size_t a = 1; a < models.size(); ++a) {
    if (models[a].inputs != models[0].inputs || models[a].outputs != models[0].outputs ||
        models[a].sample_time_min != models[0].sample_time_min) {
      throw std::invalid_argument("cross_validate: model of run '" + data[a].name +
                                  "' differs from the first in inputs, outputs or sample time");
    }
  }
  CrossValidation cv;
  cv.fit.resize(R, R);
  for (Eigen::Index a = 0; a < R; ++a) {
    for (Eigen::Index b = 0; b < R; ++b) {
      const Dataset& d = data[static_cast<std::size_t>(b)];
      std::vector<double> f;
      try {
        f = fit(models[static_cast<std::size_t>(a)], d.U, d.Y);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("cross_validate: run '" + d.name + "': " + e.what());
      }
      double sum = 0.0;
      for (const double v : f) sum += v;
      cv.fit(a, b) = sum / static_cast<double>(f.size());
    }
  }
  for (Eigen::Index a = 0; a < R; ++a) {
    CrossValidation::PerModel m;
    m.own = cv.fit(a, a);
    double sum = 0.0;
    m.cross_best = -std::numeric_limits<double>::infinity();
    m.cross_worst = std::numeric_limits<double>::infinity();
    bool any_nan = false;
    for (Eigen::Index b = 0; b < R; ++b) {
      if (b == a) continue;
      const double v = cv.fit(a, b);
      if (std::isnan(v)) {
        any_nan = true;
        continue;
      }
      sum += v;
      if (v > m.cross_best) {
        m.cross_best = v;
        m.best_on = static_cast<int>(b);
      }
      if (v < m.cross_worst) {
        m.cross_worst = v;
        m.worst_on = static_cast<int>(b);
      }
    }
    m.cross_average = any_nan ? kNaN : sum / static_cast<double>(R - 1);
    if (any_nan) {
      m.cross_best = kNaN;
      m.cross_worst = kNaN;
      m.best_on = -1;
      m.worst_on = -1;
    }
    cv.models.push_back(m);
  }
  return cv;
}

}  // namespace excite::host
