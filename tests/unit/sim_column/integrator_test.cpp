// SPDX-License-Identifier: MIT
// The Rosenbrock integrator and the block-tridiagonal solver on problems with known answers.
#include <gtest/gtest.h>

#include <unsupported/Eigen/MatrixFunctions>

#include "sim/column/block_tridiagonal.hpp"
#include "sim/column/rosenbrock.hpp"

namespace excite::sim::column {
namespace {

// ds/dt = A s with a block-tridiagonal, stiff A (eigenvalues from about −0.1 to −2000).
struct LinearChain {
  explicit LinearChain(Eigen::Index stages) : blocks(stages) {
    for (Eigen::Index j = 0; j < stages; ++j) {
      const auto b = static_cast<std::size_t>(j);
      const double d = static_cast<double>(j);
      blocks.diag[b] << -3.0 - 0.1 * d, 0.5, 0.2, -2000.0 + 10.0 * d;
      if (j > 0) blocks.lower[b] << 1.0, 0.0, 0.3, 0.1;
      if (j + 1 < stages) blocks.upper[b] << 1.2, 0.4, 0.0, 0.5;
    }
    a = blocks.dense();
  }
  Eigen::Index size() const { return a.rows(); }
  void derivative(const Eigen::VectorXd& s, Eigen::VectorXd& ds) const { ds = a * s; }
  void jacobian_blocks(const Eigen::VectorXd&, JacobianBlocks& out) const { out = blocks; }
  Eigen::MatrixXd jacobian(const Eigen::VectorXd&) const { return a; }

  JacobianBlocks blocks;
  Eigen::MatrixXd a;
};

TEST(BlockTridiagonalSolver, SolvesLikeADenseLu) {
  const LinearChain sys(9);
  BlockTridiagonalSolver solver(9);
  const Eigen::VectorXd s = Eigen::VectorXd::Zero(18);
  solver.factorise(sys, s, 7.0);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(18, -1.0, 2.0);
  Eigen::VectorXd g = rhs;
  solver.solve(g);
  const Eigen::MatrixXd m = 7.0 * Eigen::MatrixXd::Identity(18, 18) - sys.a;
  EXPECT_LT((m * g - rhs).lpNorm<Eigen::Infinity>(), 1e-12);
}

// A chain where holdups do not depend on compositions (the zero pattern of colaA).
TEST(HoldupFirstSolver, SolvesLikeADenseLuWhenHoldupsIgnoreCompositions) {
  LinearChain sys(9);
  for (std::size_t j = 0; j < 9; ++j) {
    sys.blocks.diag[j](1, 0) = 0.0;
    sys.blocks.upper[j](1, 0) = 0.0;
    sys.blocks.upper[j](0, 1) = 0.7;
    sys.blocks.lower[j] << 1.0, 0.0, 0.0, 0.0;
  }
  sys.a = sys.blocks.dense();
  HoldupFirstSolver solver(9);
  solver.factorise(sys, Eigen::VectorXd::Zero(18), 7.0);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(18, -1.0, 2.0);
  Eigen::VectorXd g = rhs;
  solver.solve(g);
  const Eigen::MatrixXd m = 7.0 * Eigen::MatrixXd::Identity(18, 18) - sys.a;
  EXPECT_LT((m * g - rhs).lpNorm<Eigen::Infinity>(), 1e-12);
}

template <class Solver>
double error_after(double tol, Solver solver, IntegrationStats* stats) {
  const LinearChain sys(6);
  Rosenbrock4<LinearChain, Solver> stepper(sys.size());
  Eigen::VectorXd s0 = Eigen::VectorXd::LinSpaced(12, 1.0, -1.0);
  Eigen::VectorXd s = s0;
  StepMemory h;
  // Ten one-unit intervals, as the plant runs them.
  for (int k = 0; k < 10; ++k) stepper.integrate(sys, solver, s, 1.0, h, {tol, tol}, stats);
  const Eigen::VectorXd exact = (sys.a * 10.0).exp() * s0;
  return (s - exact).lpNorm<Eigen::Infinity>();
}

TEST(Rosenbrock4, ErrorFollowsTheToleranceOnAStiffLinearSystem) {
  double previous = 1.0;
  for (double tol : {1e-5, 1e-7, 1e-9, 1e-11}) {
    IntegrationStats stats;
    const double err = error_after(tol, BlockTridiagonalSolver(6), &stats);
    EXPECT_LT(err, 20.0 * tol) << "tol " << tol;
    EXPECT_LT(err, previous) << "tol " << tol;
    EXPECT_GT(stats.accepted_steps, 0);
    previous = err;
  }
}

TEST(Rosenbrock4, DenseAndBlockSolversTakeTheSameSteps) {
  IntegrationStats dense_stats, block_stats;
  const double e_dense = error_after(1e-8, DenseSolver<LinearChain>(), &dense_stats);
  const double e_block = error_after(1e-8, BlockTridiagonalSolver(6), &block_stats);
  EXPECT_NEAR(e_dense, e_block, 1e-12);
  EXPECT_EQ(dense_stats.accepted_steps, block_stats.accepted_steps);
}

}  // namespace
}  // namespace excite::sim::column
