// SPDX-License-Identifier: MIT
// The dense active-set QP (sim/control/active_set_qp.hpp) against brute force: on random
// small problems every subset of constraints is tried as the active set, and the one whose
// point is feasible with multipliers >= 0 (the unique KKT point) must be the solver's; the
// solver's own answer must satisfy the KKT conditions. Warm start and infeasibility are
// counted, not timed.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "sim/control/active_set_qp.hpp"

namespace excite::sim::control {
namespace {

struct Problem {
  Eigen::MatrixXd H, A;
  Eigen::VectorXd g, b;
};

Problem random_problem(std::mt19937_64& rng, int nv, int m) {
  std::normal_distribution<double> normal;
  const auto random_matrix = [&](int rows, int cols) {
    Eigen::MatrixXd x(rows, cols);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
    return x;
  };
  Problem p;
  const Eigen::MatrixXd B = random_matrix(nv, nv);
  p.H = B.transpose() * B + 0.1 * Eigen::MatrixXd::Identity(nv, nv);
  p.A = random_matrix(m, nv);
  p.g = 3.0 * random_matrix(nv, 1);
  // Feasible by construction: a random point satisfies every row with some room.
  const Eigen::VectorXd inside = random_matrix(nv, 1);
  p.b = p.A * inside + random_matrix(m, 1).cwiseAbs();
  return p;
}

// The KKT point by enumeration: every subset of at most nv rows as equalities.
Eigen::VectorXd brute_force(const Problem& p) {
  const Eigen::Index nv = p.H.rows();
  const Eigen::Index m = p.A.rows();
  Eigen::VectorXd best;
  int found = 0;
  for (unsigned mask = 0; mask < (1U << m); ++mask) {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index j = 0; j < m; ++j) {
      if ((mask >> j) & 1U) rows.push_back(j);
    }
    const auto q = static_cast<Eigen::Index>(rows.size());
    if (q > nv) continue;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(nv + q, nv + q);
    Eigen::VectorXd rhs(nv + q);
    kkt.topLeftCorner(nv, nv) = p.H;
    rhs.head(nv) = -p.g;
    for (Eigen::Index i = 0; i < q; ++i) {
      kkt.block(0, nv + i, nv, 1) = p.A.row(rows[static_cast<std::size_t>(i)]).transpose();
      kkt.block(nv + i, 0, 1, nv) = p.A.row(rows[static_cast<std::size_t>(i)]);
      rhs(nv + i) = p.b(rows[static_cast<std::size_t>(i)]);
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(kkt);
    if (lu.rank() < nv + q) continue;
    const Eigen::VectorXd z = lu.solve(rhs);
    const Eigen::VectorXd x = z.head(nv);
    if ((p.A * x - p.b).maxCoeff() > 1e-9) continue;
    if (q > 0 && z.tail(q).minCoeff() < -1e-9) continue;
    best = x;
    ++found;
  }
  EXPECT_GE(found, 1) << "a strictly convex feasible QP has a KKT point";
  return best;
}

TEST(ActiveSetQp, RandomProblemsMatchBruteForceAndSatisfyKkt) {
  std::mt19937_64 rng(41);
  int constrained = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int nv = 1 + trial % 4;
    const int m = 1 + trial % 7;
    Problem p = random_problem(rng, nv, m);
    ActiveSetQp qp(p.H, p.A, 200);
    // Three solves with new g and b on the same H and A: the later ones start warm.
    for (int solve = 0; solve < 3; ++solve) {
      if (solve > 0) {
        const Problem again = random_problem(rng, nv, m);
        p.g = again.g;
        p.b = p.A * Eigen::VectorXd::Zero(nv) + again.b.cwiseAbs();  // 0 is feasible
      }
      Eigen::VectorXd x(nv);
      const QpResult r = qp.solve(p.g, p.b, x);
      ASSERT_EQ(r.status, QpStatus::optimal) << "trial " << trial;
      const Eigen::VectorXd expected = brute_force(p);
      EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-7)
          << "trial " << trial << " solve " << solve;
      // KKT: stationarity over the active rows, primal and dual feasibility.
      Eigen::VectorXd stationarity = p.H * x + p.g;
      const auto active = qp.active_set();
      const auto lambda = qp.multipliers();
      for (std::size_t i = 0; i < active.size(); ++i) {
        stationarity += lambda[i] * p.A.row(active[i]).transpose();
        EXPECT_GE(lambda[i], 0.0);
        EXPECT_NEAR(p.A.row(active[i]).dot(x), p.b(active[i]), 1e-8);
      }
      EXPECT_LT(stationarity.cwiseAbs().maxCoeff(), 1e-8);
      EXPECT_LE((p.A * x - p.b).maxCoeff(), 1e-8);
      constrained += active.empty() ? 0 : 1;
    }
  }
  EXPECT_GT(constrained, 300) << "most problems must have active constraints to test anything";
}

TEST(ActiveSetQp, WithNothingViolatedTheSolveIsTheUnconstrainedMinimum) {
  const Eigen::MatrixXd H = (Eigen::MatrixXd(2, 2) << 2, 0.5, 0.5, 1).finished();
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(2, 2);
  const Eigen::VectorXd g = (Eigen::VectorXd(2) << -1, 1).finished();
  ActiveSetQp qp(H, A, 50);
  Eigen::VectorXd x(2);
  const QpResult r = qp.solve(g, Eigen::VectorXd::Constant(2, 10.0), x);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.active, 0);
  EXPECT_LT((x - H.ldlt().solve(-g)).norm(), 1e-14);
}

TEST(ActiveSetQp, AWarmStartOnTheSameDataTakesNoStep) {
  std::mt19937_64 rng(7);
  Problem p = random_problem(rng, 4, 7);
  p.g *= 10.0;  // far outside: several constraints active
  ActiveSetQp qp(p.H, p.A, 200);
  Eigen::VectorXd cold(4), warm(4);
  const QpResult first = qp.solve(p.g, p.b, cold);
  ASSERT_GE(first.active, 2);
  EXPECT_GE(first.iterations, first.active);  // each active constraint added at least once
  const QpResult second = qp.solve(p.g, p.b, warm);
  EXPECT_EQ(second.iterations, 0);
  EXPECT_EQ(second.active, first.active);
  EXPECT_LT((warm - cold).cwiseAbs().maxCoeff(), 1e-12);
  qp.forget();
  const QpResult again = qp.solve(p.g, p.b, warm);
  EXPECT_EQ(again.iterations, first.iterations);
}

TEST(ActiveSetQp, ContradictoryConstraintsAreInfeasible) {
  // x ≤ −1 and x ≥ 1.
  const Eigen::MatrixXd A = (Eigen::MatrixXd(2, 1) << 1, -1).finished();
  ActiveSetQp qp(Eigen::MatrixXd::Identity(1, 1), A, 50);
  Eigen::VectorXd x(1);
  EXPECT_EQ(qp.solve(Eigen::VectorXd::Zero(1), Eigen::Vector2d(-1, -1), x).status,
            QpStatus::infeasible);
}

TEST(ActiveSetQp, TheIterationCapStopsTheSolve) {
  std::mt19937_64 rng(3);
  Problem p = random_problem(rng, 4, 7);
  p.g *= 10.0;
  ActiveSetQp qp(p.H, p.A, 1);
  Eigen::VectorXd x(4);
  EXPECT_EQ(qp.solve(p.g, p.b, x).status, QpStatus::iteration_limit);
}

TEST(ActiveSetQp, RefusesAHessianThatIsNotPositiveDefiniteAndAZeroRow) {
  const Eigen::MatrixXd semidefinite = (Eigen::MatrixXd(2, 2) << 1, 1, 1, 1).finished();
  try {
    ActiveSetQp(semidefinite, Eigen::MatrixXd::Zero(0, 2), 10);
    FAIL() << "a singular H must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "H = (not positive definite), expected a positive definite Hessian "
                 "(every move weighted)");
  }
  try {
    ActiveSetQp(Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Zero(1, 2), 10);
    FAIL() << "a zero row must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "A row 0 = 0, expected a constraint that involves a variable");
  }
}

}  // namespace
}  // namespace excite::sim::control
