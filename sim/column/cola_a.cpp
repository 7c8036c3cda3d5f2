// SPDX-License-Identifier: MIT
#include "sim/column/cola_a.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sim/column/block_tridiagonal.hpp"

namespace excite::sim::column {

// Flows of the LV column at one operating point; stage index j = 0…N−1 (0-based, from the
// bottom). "Out" is what leaves the stage's liquid (B, the tray's L_j, or L + D at the top),
// "in" what arrives from the stage above (the tray overflow, or the reflux L).
class ColaA::System {
 public:
  System(const ColaAParameters& p, Eigen::Index stages)
      : p_(p),
        n_(stages),
        feed_(p.feed_stage - 1),
        y_(stages),
        k_(stages),
        v_in_(stages),
        v_out_(stages),
        feed_in_(stages),
        out_c_(stages),
        out_s_(stages),
        in_c_(stages),
        in_s_(stages) {}

  /// Tabulates the flows at op: every liquid flow is affine in one holdup, so the
  /// derivative below is one branch-light sweep.
  void set_operating(const Operating& op) {
    op_ = op;
    const double q = p_.feed_liquid_fraction;
    const Operating& nom = p_.nominal;
    for (Eigen::Index j = 0; j < n_; ++j) {
      v_out_[j] = j == n_ - 1  ? 0.0
                  : j >= feed_ ? op.boilup_kmol_min + (1.0 - q) * op.feed_kmol_min
                               : op.boilup_kmol_min;
      v_in_[j] = j == 0 ? 0.0 : v_out_[j - 1];
      feed_in_[j] = j == feed_ ? op.feed_kmol_min : 0.0;
    }
    const double m0 = p_.holdup_kmol;
    const double k = p_.level_gain_per_min;
    for (Eigen::Index j = 0; j < n_; ++j) {
      if (j == 0) {  // B = B₀ + K(M − M₀)
        out_s_[j] = k;
        out_c_[j] = p_.bottoms_bias_kmol_min - k * m0;
      } else if (j == n_ - 1) {  // L + D, D = D₀ + K(M − M₀)
        out_s_[j] = k;
        out_c_[j] = op.reflux_kmol_min + p_.distillate_bias_kmol_min - k * m0;
      } else {  // L_j = L₀_j + (M_j − M₀)/τ_L + λ(V_{j−1} − V₀_j)
        const bool stripping = j <= feed_;
        const double l0 = nom.reflux_kmol_min + (stripping ? q * nom.feed_kmol_min : 0.0);
        const double v0 = nom.boilup_kmol_min + (stripping ? 0.0 : (1.0 - q) * nom.feed_kmol_min);
        out_s_[j] = 1.0 / p_.liquid_time_constant_min;
        out_c_[j] = l0 - m0 * out_s_[j] + p_.vapour_liquid_coupling * (v_in_[j] - v0);
      }
    }
    for (Eigen::Index j = 0; j < n_; ++j) {
      if (j == n_ - 1) {  // the condenser receives no liquid
        in_c_[j] = in_s_[j] = 0.0;
      } else if (j + 1 == n_ - 1) {  // the top tray receives the reflux
        in_c_[j] = op.reflux_kmol_min;
        in_s_[j] = 0.0;
      } else {
        in_c_[j] = out_c_[j + 1];
        in_s_[j] = out_s_[j + 1];
      }
    }
  }
  Eigen::Index size() const { return 2 * n_; }

  /// Liquid leaving stage j at holdup m: B, the tray overflow, or L + D at the top.
  double liquid_out(Eigen::Index j, double m) const { return out_c_[j] + out_s_[j] * m; }

  void derivative(const Eigen::VectorXd& s, Eigen::VectorXd& ds) const {
    equilibrium(s);
    const double* st = s.data();
    double* d = ds.data();
    for (Eigen::Index j = 0; j < n_; ++j) {
      const double x = st[2 * j];
      const double m = st[2 * j + 1];
      const bool top = j == n_ - 1;
      const double x_above = top ? x : st[2 * j + 2];
      const double m_above = top ? 0.0 : st[2 * j + 3];
      const double y_below = j > 0 ? y_[j - 1] : x;
      const double l_in = in_c_[j] + in_s_[j] * m_above;
      const double f = feed_in_[j];
      // A.1.3 divided by M_j with A.1.1 substituted: the outflow L_j drops out.
      const double num = l_in * (x_above - x) + v_in_[j] * (y_below - x) - v_out_[j] * (y_[j] - x) +
                         f * (op_.feed_light - x);
      d[2 * j] = num / m;
      d[2 * j + 1] = l_in - liquid_out(j, m) + v_in_[j] - v_out_[j] + f;  // A.1.1
    }
  }

  void jacobian_blocks(const Eigen::VectorXd& s, JacobianBlocks& jb) const {
    equilibrium(s);
    for (Eigen::Index j = 0; j < n_; ++j) {
      const auto b = static_cast<std::size_t>(j);
      const double x = s[2 * j];
      const double m = s[2 * j + 1];
      const bool top = j == n_ - 1;
      const double x_above = top ? x : s[2 * j + 2];
      const double m_above = top ? 0.0 : s[2 * j + 3];
      const double y_below = j > 0 ? y_[j - 1] : x;
      const double l_in = in_c_[j] + in_s_[j] * m_above;
      const double v_in = v_in_[j];
      const double v_out = v_out_[j];
      const double f = feed_in_[j];
      const double num = l_in * (x_above - x) + v_in * (y_below - x) - v_out * (y_[j] - x) +
                         f * (op_.feed_light - x);
      Eigen::Matrix2d& dg = jb.diag[b];
      dg(0, 0) = (-l_in - v_in - v_out * (k_[j] - 1.0) - f) / m;
      dg(0, 1) = -num / (m * m);
      dg(1, 0) = 0.0;
      dg(1, 1) = -out_s_[j];
      if (!top) {
        Eigen::Matrix2d& u = jb.upper[b];
        u(0, 0) = l_in / m;
        u(0, 1) = in_s_[j] * (x_above - x) / m;
        u(1, 0) = 0.0;
        u(1, 1) = in_s_[j];
      }
      if (j > 0) {
        Eigen::Matrix2d& l = jb.lower[b];
        l.setZero();
        l(0, 0) = v_in * k_[j - 1] / m;
      }
    }
  }

 private:
  // y_j = α x_j / (1 + (α − 1) x_j) (A.1.4 with E = 1) and K_j = dy_j/dx_j.
  void equilibrium(const Eigen::VectorXd& s) const {
    const double a = p_.relative_volatility;
    for (Eigen::Index j = 0; j < n_; ++j) {
      const double x = s[2 * j];
      const double inv = 1.0 / (1.0 + (a - 1.0) * x);
      y_[j] = a * x * inv;
      k_[j] = a * inv * inv;
    }
  }

  const ColaAParameters& p_;
  Eigen::Index n_;
  Eigen::Index feed_;
  Operating op_{};
  mutable Eigen::VectorXd y_, k_;
  // Flows at op_, per stage j (kmol/min): vapour in/out, feed, and the liquid flows as
  // affine functions of a holdup: out = out_c + out_s·M_j, in = in_c + in_s·M_{j+1}.
  Eigen::VectorXd v_in_, v_out_, feed_in_, out_c_, out_s_, in_c_, in_s_;
};

struct ColaA::Workspace {
  Workspace(const ColaAParameters& p, Eigen::Index stages)
      : system(p, stages), probe(p, stages), solver(stages), stepper(2 * stages) {}
  System system;
  System probe;              // flows for products() and check_state(), so they allocate nothing
  HoldupFirstSolver solver;  // constant molar flows: holdups do not depend on x
  Rosenbrock4<System, HoldupFirstSolver> stepper;
};

ColaA::ColaA(ColaAParameters p) : p_(p), stages_(p.stages) {
  if (p_.stages < 3 || p_.feed_stage < 2 || p_.feed_stage > p_.stages - 1) {
    std::ostringstream msg;
    msg << "colaA: stages = " << p_.stages << ", feed_stage = " << p_.feed_stage
        << ", expected at least 3 stages and the feed on a tray (2…stages−1)";
    throw std::invalid_argument(msg.str());
  }
  if (!(p_.holdup_kmol > 0.0 && p_.liquid_time_constant_min > 0.0 && p_.relative_volatility > 0.0 &&
        p_.level_gain_per_min > 0.0)) {
    throw std::invalid_argument(
        "colaA: holdup, τ_L, relative volatility and level gain must be positive");
  }
  validate(p_.nominal, "colaA nominal operating point");
}

ColaA::~ColaA() = default;

std::vector<std::string> ColaA::state_names() const {
  std::vector<std::string> names;
  for (Eigen::Index j = 1; j <= stages_; ++j) {
    names.push_back("x[" + std::to_string(j) + "]");
    names.push_back("M[" + std::to_string(j) + "]");
  }
  return names;
}

void ColaA::derivative(const Eigen::VectorXd& s, const Operating& op, Eigen::VectorXd& ds) const {
  System sys(p_, stages_);
  sys.set_operating(op);
  ds.resize(state_size());
  sys.derivative(s, ds);
}

Eigen::MatrixXd ColaA::jacobian(const Eigen::VectorXd& s, const Operating& op) const {
  System sys(p_, stages_);
  sys.set_operating(op);
  JacobianBlocks jb(stages_);
  sys.jacobian_blocks(s, jb);
  return jb.dense();
}

Eigen::VectorXd ColaA::initial_guess(const Operating& op) const {
  Eigen::VectorXd s(state_size());
  (void)op;
  for (Eigen::Index j = 0; j < stages_; ++j) {
    s[2 * j] = 0.05 + 0.9 * static_cast<double>(j) / static_cast<double>(stages_ - 1);
    s[2 * j + 1] = p_.holdup_kmol;
  }
  return s;
}

void ColaA::prepare() const {
  if (!work_) work_ = std::make_unique<Workspace>(p_, stages_);
}

Products ColaA::products(const Eigen::VectorXd& s, const Operating& op) const {
  prepare();
  System& sys = work_->probe;
  sys.set_operating(op);
  const Eigen::Index top = stages_ - 1;
  return Products{sys.liquid_out(top, s[2 * top + 1]) - op.reflux_kmol_min, sys.liquid_out(0, s[1]),
                  s[2 * top], s[0]};
}

void ColaA::check_state(const Eigen::VectorXd& s) const {
  for (Eigen::Index j = 0; j < stages_; ++j) {
    const double x = s[2 * j];
    const double m = s[2 * j + 1];
    if (!std::isfinite(x) || !std::isfinite(m) || m <= 0.0 || x < -1e-6 || x > 1.0 + 1e-6) {
      std::ostringstream msg;
      msg << "colaA: stage " << j + 1 << " left the physical range (holdup M = " << m
          << " kmol, x = " << x << "); the inputs drain or flood it — expected M > 0 and 0 ≤ x ≤ 1";
      throw std::invalid_argument(msg.str());
    }
  }
  // Liquid flows leaving each stage (B, tray overflows, L + D) must not be negative: a
  // negative one means the inputs empty that stage. λ(V − V₀) is taken at the nominal V.
  prepare();
  System& sys = work_->probe;
  sys.set_operating(p_.nominal);
  for (Eigen::Index j = 0; j < stages_; ++j) {
    double out = sys.liquid_out(j, s[2 * j + 1]);
    if (j == stages_ - 1) out -= p_.nominal.reflux_kmol_min;  // D alone
    if (out < 0.0) {
      std::ostringstream msg;
      msg << "colaA: stage " << j + 1 << " would need a negative outflow ("
          << (j == 0             ? "B"
              : j == stages_ - 1 ? "D"
                                 : "L")
          << " = " << out << " kmol/min at holdup " << s[2 * j + 1]
          << " kmol); the inputs drain it — expected flows ≥ 0";
      throw std::invalid_argument(msg.str());
    }
  }
}

void ColaA::integrate(Eigen::VectorXd& s, const Operating& op, double duration_min,
                      StepMemory& steps, const Tolerance& tol, IntegrationStats* stats) const {
  validate(op, "colaA inputs");
  prepare();
  work_->system.set_operating(op);
  work_->stepper.integrate(work_->system, work_->solver, s, duration_min, steps, tol, stats);
  check_state(s);
}

}  // namespace excite::sim::column
