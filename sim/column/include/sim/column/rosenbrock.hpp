// SPDX-License-Identifier: MIT
#pragma once
// Adaptive Rosenbrock integration of an autonomous stiff ODE ds/dt = f(s).
//
// The method is Boost.Odeint's rosenbrock4: the same coefficients
// (boost::numeric::odeint::default_rosenbrock_coefficients, Hairer & Wanner's 6-stage
// stiffly accurate order-4(3) pair) and the same stage recursion
//   (I/(γh) − J) g_k = f(s + Σ a_kj g_j) + Σ c_kj g_j / h,
// with an error controller like odeint's rosenbrock4_controller. What differs is the
// linear algebra: odeint factorises a dense ublas matrix, O(n³) per step; here the
// solver is a template parameter, so the column's block-tridiagonal Jacobian is
// factorised in O(n) (sim/column/block_tridiagonal.hpp). The inputs are held over each
// call (zero-order hold), so the system is autonomous and ∂f/∂t = 0.
//
// System:  Eigen::Index size() const;
//          void derivative(const Eigen::VectorXd& s, Eigen::VectorXd& ds) const;
// Solver:  void factorise(const System&, const Eigen::VectorXd& s, double shift);
//              // factorises shift·I − J(s)
//          void solve(Eigen::VectorXd& rhs) const;   // in place

#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint/stepper/rosenbrock4.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

namespace excite::sim::column {

/// Error tolerances of the step controller: a step is accepted when the root-mean-square
/// over the components of error estimate / (absolute + relative·max(|s_old|, |s_new|))
/// is at most 1. `max_steps` caps the work of one integrate() call: at most that many
/// attempted steps (accepted + rejected), each one Jacobian factorisation, six derivative
/// evaluations and six solves; 0 means no cap.
struct Tolerance {
  double absolute = 1e-9;
  double relative = 1e-9;
  long max_steps = 0;
};

/// Step-size memory carried from one integrate() call to the next (one per trajectory):
/// the proposal for the next step and the first accepted step of the last call.
struct StepMemory {
  double proposal = 0.0;
  double first = 0.0;
};

/// Work counters, for benchmarks and tests.
struct IntegrationStats {
  long accepted_steps = 0;
  long rejected_steps = 0;
};

template <class System, class Solver>
class Rosenbrock4 {
 public:
  explicit Rosenbrock4(Eigen::Index n)
      : f0_(n), f_(n), stage_(n), g1_(n), g2_(n), g3_(n), g4_(n), g5_(n), err_(n), out_(n) {}

  /// Advances s over `duration` (same time unit as the system), starting with the step
  /// proposed in `memory` and leaving there the proposal for the next call. Every call is
  /// taken to start just after an input change, so its first step is also capped at 1.5
  /// times the first accepted step of the previous call (that step resolved the same kind
  /// of fast transient; this saves a rejected step per sample). The result depends only on
  /// (s, memory), never on earlier use of this object. Throws std::runtime_error if the
  /// step size collapses or tol.max_steps attempts do not reach the end (s and memory are
  /// then partly advanced: the caller keeps its own copy to roll back).
  void integrate(const System& sys, Solver& solver, Eigen::VectorXd& s, double duration,
                 StepMemory& memory, const Tolerance& tol, IntegrationStats* stats = nullptr) {
    double t = 0.0;
    double h = std::min(memory.proposal > 0.0 ? memory.proposal : duration, duration);
    if (memory.first > 0.0) h = std::min(h, 1.5 * memory.first);
    bool first = true;
    long attempts = 0;
    while (t < duration) {
      if (tol.max_steps > 0 && attempts == tol.max_steps) {
        throw std::runtime_error("Rosenbrock4: " + std::to_string(attempts) +
                                 " steps did not reach the end of the interval (max_steps)");
      }
      ++attempts;
      const double remaining = duration - t;
      // Land on the end: the last step takes what remains; when less than two steps
      // remain, two equal steps replace a full one and a sliver.
      const bool last = h >= remaining * (1.0 - 1e-12);
      const double step = last ? remaining : (remaining < 2.0 * h ? 0.5 * remaining : h);
      try_step(sys, solver, s, step);
      const double err = error_norm(s, tol);
      if (err <= 1.0) {
        s.swap(out_);
        t = last ? duration : t + step;
        if (stats) ++stats->accepted_steps;
        if (first) memory.first = step;
        first = false;
        const double grow = err > 0.0 ? 0.9 * std::pow(err, -0.25) : 5.0;
        const double proposal = step * std::clamp(grow, 0.2, 5.0);
        h = step < h ? std::max(h, proposal) : proposal;  // a shortened step keeps h
      } else {
        if (stats) ++stats->rejected_steps;
        h = step * std::max(0.9 * std::pow(err, -1.0 / 3.0), 0.2);
        if (h < duration * 1e-14 || h < 1e-14) {
          throw std::runtime_error("Rosenbrock4: step size underflow");
        }
      }
    }
    memory.proposal = h;
  }

 private:
  // One step of length h from s into out_, with the embedded error estimate in err_.
  void try_step(const System& sys, Solver& solver, const Eigen::VectorXd& s, double h) {
    const auto& c = coef_;
    const double inv_h = 1.0 / h;
    sys.derivative(s, f0_);
    solver.factorise(sys, s, 1.0 / (c.gamma * h));

    g1_ = f0_;
    solver.solve(g1_);

    stage_ = s + c.a21 * g1_;
    sys.derivative(stage_, f_);
    g2_ = f_ + (c.c21 * inv_h) * g1_;
    solver.solve(g2_);

    stage_ = s + c.a31 * g1_ + c.a32 * g2_;
    sys.derivative(stage_, f_);
    g3_ = f_ + inv_h * (c.c31 * g1_ + c.c32 * g2_);
    solver.solve(g3_);

    stage_ = s + c.a41 * g1_ + c.a42 * g2_ + c.a43 * g3_;
    sys.derivative(stage_, f_);
    g4_ = f_ + inv_h * (c.c41 * g1_ + c.c42 * g2_ + c.c43 * g3_);
    solver.solve(g4_);

    stage_ = s + c.a51 * g1_ + c.a52 * g2_ + c.a53 * g3_ + c.a54 * g4_;
    sys.derivative(stage_, f_);
    g5_ = f_ + inv_h * (c.c51 * g1_ + c.c52 * g2_ + c.c53 * g3_ + c.c54 * g4_);
    solver.solve(g5_);

    stage_ += g5_;
    sys.derivative(stage_, f_);
    err_ = f_ + inv_h * (c.c61 * g1_ + c.c62 * g2_ + c.c63 * g3_ + c.c64 * g4_ + c.c65 * g5_);
    solver.solve(err_);
    out_ = stage_ + err_;
  }

  // Root-mean-square of the scaled error estimate (Hairer & Wanner's norm).
  double error_norm(const Eigen::VectorXd& s, const Tolerance& tol) const {
    double sum = 0.0;
    for (Eigen::Index i = 0; i < s.size(); ++i) {
      if (!std::isfinite(out_[i])) return 1e10;  // reject; the controller shrinks the step
      const double scale =
          tol.absolute + tol.relative * std::max(std::abs(s[i]), std::abs(out_[i]));
      const double e = err_[i] / scale;
      sum += e * e;
    }
    return std::sqrt(sum / static_cast<double>(s.size()));
  }

  boost::numeric::odeint::default_rosenbrock_coefficients<double> coef_;
  Eigen::VectorXd f0_, f_, stage_, g1_, g2_, g3_, g4_, g5_, err_, out_;
};

/// Dense solver for small systems: partial-pivot LU of shift·I − J, with J from
/// System::jacobian_into(s, J) when the system has it (no allocation once the buffers have
/// their size), else from System::jacobian(s) (an n×n Eigen matrix).
template <class System>
class DenseSolver {
 public:
  /// n: the system size, to size the buffers up front (0: on first use).
  explicit DenseSolver(Eigen::Index n = 0) : m_(n, n), lu_(n), work_(n) {}

  void factorise(const System& sys, const Eigen::VectorXd& s, double shift) {
    if constexpr (requires { sys.jacobian_into(s, m_); }) {
      sys.jacobian_into(s, m_);
      m_ = -m_;
    } else {
      m_ = -sys.jacobian(s);
    }
    m_.diagonal().array() += shift;
    lu_.compute(m_);
  }
  void solve(Eigen::VectorXd& rhs) const {
    work_ = rhs;
    rhs.noalias() = lu_.solve(work_);
  }

 private:
  Eigen::MatrixXd m_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  mutable Eigen::VectorXd work_;
};

}  // namespace excite::sim::column
