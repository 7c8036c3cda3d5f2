// SPDX-License-Identifier: MIT
#pragma once
// Two records of the same experiment compared in full (tests/hil/loop/campaign_test): the run
// logs row by row with no realignment (the same rows, k, inputs and outputs), and the models
// identified from them parameter by parameter. The tolerances are the caller's: what float32
// registers on the wire explain.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "firmware/runlog/format.hpp"
#include "firmware/runlog/reader.hpp"

namespace excite::test {

struct RunDifference {
  double du = 0.0;  // largest |Δdu| over every row and input
  double dy = 0.0;  // largest |Δdy| over every row and output
};

/// `a` (the gateway's log) has b's rows and then only the rows that end the run (state
/// completed, returning or safe, every du 0: the gateway logs them, a simulation does not); on
/// b's rows k, t, every du and every dy agree row for row to du_tolerance and dy_tolerance.
/// An input one row late, a missing or an extra running row fails.
inline RunDifference expect_same_run(const runlog::RunLog& a, const runlog::RunLog& b,
                                     double du_tolerance, double dy_tolerance,
                                     const std::string& what) {
  RunDifference d;
  const std::size_t rows = b.rows();
  EXPECT_GE(a.rows(), rows) << what;
  EXPECT_EQ(a.du.size(), b.du.size()) << what;
  EXPECT_EQ(a.dy.size(), b.dy.size()) << what;
  if (a.rows() < rows || a.du.size() != b.du.size() || a.dy.size() != b.dy.size()) return d;
  for (std::size_t r = rows; r < a.rows(); ++r) {
    const runlog::RunState s = a.state[r];
    EXPECT_TRUE(s == runlog::RunState::completed || s == runlog::RunState::returning ||
                s == runlog::RunState::safe)
        << what << ": row " << r << " past the simulated run is not an end-of-run row";
    for (const auto& du : a.du) EXPECT_EQ(du[r], 0.0) << what << ": row " << r;
  }
  EXPECT_TRUE(std::equal(b.k.begin(), b.k.end(), a.k.begin())) << what << ": k differs";
  EXPECT_TRUE(std::equal(b.t_min.begin(), b.t_min.end(), a.t_min.begin())) << what << ": t";
  std::size_t bad = 0;
  const auto compare = [&](const auto& x, const auto& y, double tolerance, double& largest,
                           const char* column) {
    for (std::size_t c = 0; c < x.size(); ++c) {
      for (std::size_t r = 0; r < rows; ++r) {
        const double diff = std::abs(x[c][r] - y[c][r]);
        largest = std::max(largest, diff);
        if (diff > tolerance && ++bad <= 5) {
          ADD_FAILURE() << what << ": " << column << "[" << c << "] row " << r << ": " << x[c][r]
                        << " against " << y[c][r];
        }
      }
    }
  };
  compare(a.du, b.du, du_tolerance, d.du, "du");
  compare(a.dy, b.dy, dy_tolerance, d.dy, "dy");
  EXPECT_EQ(bad, 0U) << what << ": rows differing (first 5 shown)";
  return d;
}

struct ModelTolerance {
  double fit_points = 1e-4;       // each output's fit, in points of %
  double standard_errors = 0.02;  // a parameter with a standard error: |Δ| ≤ this many of b's σ
  double undetermined_min = 0.05;  // a parameter without one (at a bound: T_d against T_p2)
};

/// The model files (excite identify / campaign, host/export/model_file.cpp) of `a` and `b`: the
/// same inputs, outputs and status per element; each output's fit, and each of K, T_d, T_p1,
/// T_p2 within `tol`. Returns the largest |Δ| in units of b's standard error.
inline double expect_same_model(const nlohmann::json& a, const nlohmann::json& b,
                                const ModelTolerance& tol, const std::string& what) {
  double largest = 0.0;
  EXPECT_EQ(a["inputs"], b["inputs"]) << what;
  EXPECT_EQ(a["outputs"].size(), b["outputs"].size()) << what;
  if (a["outputs"].size() != b["outputs"].size()) return largest;
  for (std::size_t o = 0; o < a["outputs"].size(); ++o) {
    const auto& x = a["outputs"][o];
    const auto& y = b["outputs"][o];
    EXPECT_EQ(x["name"], y["name"]) << what;
    if (x["fit"].is_number() && y["fit"].is_number()) {
      EXPECT_NEAR(x["fit"].get<double>(), y["fit"].get<double>(), tol.fit_points)
          << what << " output " << o;
    } else {
      EXPECT_EQ(x["fit"], y["fit"]) << what << " output " << o;
    }
    EXPECT_EQ(x["elements"].size(), y["elements"].size()) << what;
    for (std::size_t i = 0; i < std::min(x["elements"].size(), y["elements"].size()); ++i) {
      const auto& ex = x["elements"][i];
      const auto& ey = y["elements"][i];
      const std::string where = "element (" + std::to_string(o) + "," + std::to_string(i) + ")";
      EXPECT_EQ(ex["status"], ey["status"]) << what << " " << where;
      for (const char* key : {"K", "Td", "Tp1", "Tp2"}) {
        if (!ex[key].is_number() || !ey[key].is_number()) {
          EXPECT_EQ(ex[key], ey[key]) << what << " " << where << " " << key;
          continue;
        }
        const double diff = std::abs(ex[key].get<double>() - ey[key].get<double>());
        // "se" holds the structure's free parameters only (a first-order element has no T_p2
        // there): a parameter it lacks is compared as undetermined.
        const nlohmann::json se =
            ey.contains("se") && ey["se"].contains(key) ? ey["se"][key] : nlohmann::json();
        if (se.is_number() && std::isfinite(se.get<double>()) && se.get<double>() > 0.0) {
          largest = std::max(largest, diff / se.get<double>());
          EXPECT_LE(diff, tol.standard_errors * se.get<double>())
              << what << " " << where << " " << key << ": " << ex[key] << " against " << ey[key]
              << " ± " << se;
        } else {
          EXPECT_LE(diff, tol.undetermined_min)
              << what << " " << where << " " << key << " (no standard error): " << ex[key]
              << " against " << ey[key];
        }
      }
    }
  }
  return largest;
}

}  // namespace excite::test
