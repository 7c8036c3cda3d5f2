// SPDX-License-Identifier: MIT
#include "sim/column/pilot15.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace excite::sim::column {

// The ODE at one operating point. Index helpers follow the state layout of pilot15.hpp.
class Pilot15::System {
 public:
  explicit System(const Pilot15& m)
      : m_(m),
        p_(m.p_),
        n_(p_.trays),
        y_(static_cast<std::size_t>(p_.trays + 2)),
        sp_(m.state_size()),
        up_(m.state_size()),
        down_(m.state_size()) {}

  void set_operating(const Operating& op) { op_ = op; }
  Eigen::Index size() const { return m_.state_size(); }

  Eigen::Index x(int stage) const { return 2 * stage; }
  Eigen::Index hold(int stage) const { return 2 * stage + 1; }
  Eigen::Index xr() const { return 2 * (n_ + 1); }
  Eigen::Index vb() const { return 2 * (n_ + 1) + 1; }
  Eigen::Index mb() const { return 2 * (n_ + 1) + 2; }
  Eigen::Index lb() const { return 2 * (n_ + 1) + 3; }

  /// x_{N+1}: the liquid leaving the reboiler tubes, from A.1.18–A.1.19 given x_r:
  /// (1 − (1−R)(1−E_r)) x_r = R x_{N+1} + (1−R) E_r y*(x_{N+1}); secant iteration.
  double reboiler_liquid(double x_r) const {
    const double big_r = p_.liquid_return_fraction;
    const double e = p_.reboiler_efficiency;
    const double lhs = (1.0 - (1.0 - big_r) * (1.0 - e)) * x_r;
    auto h = [&](double v) {
      return big_r * v + (1.0 - big_r) * e * m_.vle_.bubble_point(v).y - lhs;
    };
    double a = 0.5 * x_r, b = x_r;
    double ha = h(a), hb = h(b);
    for (int it = 0; it < 60 && std::abs(b - a) > 1e-15; ++it) {
      if (hb == ha) break;
      const double c = b - hb * (b - a) / (hb - ha);
      a = b;
      ha = hb;
      b = c;
      hb = h(b);
    }
    return b;
  }

  void derivative(const Eigen::VectorXd& s, Eigen::VectorXd& ds) const {
    const double vapour = s[vb()];
    const double x_out = reboiler_liquid(s[xr()]);
    const double e = p_.murphree_efficiency;
    // Vapour compositions bottom-up: A.1.19 for the reboiler, A.1.4 for the trays.
    y_[static_cast<std::size_t>(n_ + 1)] = p_.reboiler_efficiency * m_.vle_.bubble_point(x_out).y +
                                           (1.0 - p_.reboiler_efficiency) * s[xr()];
    for (int i = n_; i >= 1; --i) {
      const auto k = static_cast<std::size_t>(i);
      y_[k] = e * m_.vle_.bubble_point(s[x(i)]).y + (1.0 - e) * y_[k + 1];
    }
    // Condenser and reflux drum, A.1.6–A.1.7.
    const double distillate =
        m_.distillate_bias_ + p_.drum_level_gain_per_min * (s[hold(0)] - p_.drum_holdup_kmol);
    ds[hold(0)] = vapour - op_.reflux_kmol_min - distillate;
    ds[x(0)] = vapour * (y_[1] - s[x(0)]) / s[hold(0)];
    // Trays, A.1.1 and A.1.3 (constant molar overflow: V_i = V_{N+1}).
    double liquid_in = op_.reflux_kmol_min;
    for (int i = 1; i <= n_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double xi = s[x(i)];
      const double m = s[hold(i)];
      const double f = i == p_.feed_tray ? op_.feed_kmol_min : 0.0;
      const double liquid_out = m_.weir_flow(m, xi);
      ds[hold(i)] = liquid_in - liquid_out + f;
      ds[x(i)] = (vapour * (y_[k + 1] - y_[k]) + liquid_in * (s[x(i - 1)] - xi) +
                  f * (op_.feed_light - xi)) /
                 m;
      liquid_in = liquid_out;
    }
    // Reboiler compartment and thermosyphon, A.1.10–A.1.12, A.1.17 (corrected).
    const double big_r = p_.liquid_return_fraction;
    const double r = p_.compartment_return_fraction;
    const double l_n = liquid_in;
    const double l_r = vapour / (1.0 - big_r);
    const double l_b = l_n - (1.0 - r * big_r) * l_r;
    const double x_b = (l_n * s[x(n_)] + r * big_r * l_r * x_out) / (l_n + r * big_r * l_r);
    ds[xr()] = l_r * (x_b - s[xr()]) / p_.reboiler_holdup_kmol;
    // Heat input, A.1.15–A.1.16 divided by h_V.
    ds[vb()] = (op_.boilup_kmol_min - vapour) / p_.heat_time_constant_min;
    // Sump, A.1.13–A.1.14.
    const double bottoms =
        m_.bottoms_bias_ + p_.sump_level_gain_per_min * (s[mb()] - p_.sump_holdup_kmol);
    const double returned = (1.0 - r) * big_r * l_r;
    ds[mb()] = l_b + returned - bottoms;
    ds[lb()] = l_b * x_b + returned * x_out - bottoms * s[lb()] / s[mb()];
  }

  Eigen::MatrixXd jacobian(const Eigen::VectorXd& s) const {
    Eigen::MatrixXd j(size(), size());
    jacobian_into(s, j);
    return j;
  }

  /// ∂f/∂s by central differences into j (n×n; no allocation when it has that size).
  void jacobian_into(const Eigen::VectorXd& s, Eigen::MatrixXd& j) const {
    const Eigen::Index n = size();
    j.resize(n, n);
    sp_ = s;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double h = 6e-6 * std::max(std::abs(s[k]), 1e-2);
      sp_[k] = s[k] + h;
      derivative(sp_, up_);
      sp_[k] = s[k] - h;
      derivative(sp_, down_);
      sp_[k] = s[k];
      j.col(k) = (up_ - down_) / (2.0 * h);
    }
  }

 private:
  const Pilot15& m_;
  const Pilot15Parameters& p_;
  int n_;
  Operating op_{};
  mutable std::vector<double> y_;
  mutable Eigen::VectorXd sp_, up_, down_;  // Jacobian scratch
};

struct Pilot15::Workspace {
  explicit Workspace(const Pilot15& m)
      : system(m), solver(m.state_size()), stepper(m.state_size()) {}
  System system;
  DenseSolver<System> solver;
  Rosenbrock4<System, DenseSolver<System>> stepper;
};

Pilot15::Pilot15(Pilot15Parameters p) : p_(p), vle_(p.pressure_kpa) {
  if (p_.trays < 2 || p_.feed_tray < 1 || p_.feed_tray > p_.trays) {
    std::ostringstream msg;
    msg << "pilot15: trays = " << p_.trays << ", feed_tray = " << p_.feed_tray
        << ", expected at least 2 trays and the feed on one of them";
    throw std::invalid_argument(msg.str());
  }
  if (!(p_.liquid_return_fraction >= 0.0 && p_.liquid_return_fraction < 1.0 &&
        p_.compartment_return_fraction >= 0.0 && p_.compartment_return_fraction <= 1.0)) {
    throw std::invalid_argument("pilot15: R = " + std::to_string(p_.liquid_return_fraction) +
                                ", r = " + std::to_string(p_.compartment_return_fraction) +
                                ", expected 0 ≤ R < 1 and 0 ≤ r ≤ 1");
  }
  validate(p_.nominal, "pilot15 nominal operating point");
  distillate_bias_ = p_.nominal.boilup_kmol_min - p_.nominal.reflux_kmol_min;
  bottoms_bias_ = p_.nominal.feed_kmol_min - distillate_bias_;
  if (distillate_bias_ <= 0.0 || bottoms_bias_ <= 0.0) {
    throw std::invalid_argument(
        "pilot15: nominal V − L (distillate) and F − (V − L) (bottoms) must be positive");
  }
}

Pilot15::~Pilot15() = default;

double Pilot15::weir_flow(double m, double x) const {
  const double xc = std::clamp(x, 0.0, 1.0);
  const double molar_volume =
      xc * p_.ethanol_molar_volume_m3_kmol + (1.0 - xc) * p_.water_molar_volume_m3_kmol;
  const double crest_m = m * molar_volume / p_.tray_area_m2 - p_.weir_height_m;
  if (crest_m <= 0.0) return 0.0;
  const double q_m3_s = p_.francis_coefficient * p_.weir_length_m * std::pow(crest_m, 1.5);
  return 60.0 * q_m3_s / molar_volume;
}

std::vector<std::string> Pilot15::state_names() const {
  std::vector<std::string> names;
  for (int i = 0; i <= p_.trays; ++i) {
    names.push_back("x[" + std::to_string(i) + "]");
    names.push_back("M[" + std::to_string(i) + "]");
  }
  for (const char* n : {"x_r", "V_reb", "M_B", "m_B"}) names.emplace_back(n);
  return names;
}

void Pilot15::derivative(const Eigen::VectorXd& s, const Operating& op, Eigen::VectorXd& ds) const {
  System sys(*this);
  sys.set_operating(op);
  ds.resize(state_size());
  sys.derivative(s, ds);
}

Eigen::MatrixXd Pilot15::jacobian(const Eigen::VectorXd& s, const Operating& op) const {
  System sys(*this);
  sys.set_operating(op);
  return sys.jacobian(s);
}

Eigen::VectorXd Pilot15::initial_guess(const Operating& op) const {
  Eigen::VectorXd s(state_size());
  const double crest = 0.002;  // m, a typical crest over the weir
  for (int i = 0; i <= p_.trays; ++i) {
    const double frac = static_cast<double>(i) / static_cast<double>(p_.trays);
    const double xi = 0.8 * (1.0 - frac) + 0.01 * frac;
    const double v =
        xi * p_.ethanol_molar_volume_m3_kmol + (1.0 - xi) * p_.water_molar_volume_m3_kmol;
    s[2 * i] = xi;
    s[2 * i + 1] = i == 0 ? p_.drum_holdup_kmol : p_.tray_area_m2 * (p_.weir_height_m + crest) / v;
  }
  const Eigen::Index r = 2 * (p_.trays + 1);
  s[r] = 0.01;
  s[r + 1] = op.boilup_kmol_min;
  s[r + 2] = p_.sump_holdup_kmol;
  s[r + 3] = 0.01 * p_.sump_holdup_kmol;
  return s;
}

Products Pilot15::products(const Eigen::VectorXd& s, const Operating& op) const {
  (void)op;
  const Eigen::Index r = 2 * (p_.trays + 1);
  const double d = distillate_bias_ + p_.drum_level_gain_per_min * (s[1] - p_.drum_holdup_kmol);
  const double b = bottoms_bias_ + p_.sump_level_gain_per_min * (s[r + 2] - p_.sump_holdup_kmol);
  return Products{d, b, s[0], s[r + 3] / s[r + 2]};
}

double Pilot15::compartment_overflow(const Eigen::VectorXd& s) const {
  const double l_n = weir_flow(s[2 * p_.trays + 1], s[2 * p_.trays]);
  const double vapour = s[2 * (p_.trays + 1) + 1];
  const double l_r = vapour / (1.0 - p_.liquid_return_fraction);
  return l_n - (1.0 - p_.compartment_return_fraction * p_.liquid_return_fraction) * l_r;
}

Eigen::VectorXd Pilot15::tray_temperatures_c(const Eigen::VectorXd& s) const {
  Eigen::VectorXd t(p_.trays + 1);
  for (int i = 0; i <= p_.trays; ++i) t[i] = vle_.bubble_point(s[2 * i]).temperature_c;
  return t;
}

void Pilot15::check_state(const Eigen::VectorXd& s) const {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("pilot15: " + what +
                                "; the inputs drain or flood the column beyond its range");
  };
  for (Eigen::Index k = 0; k < s.size(); ++k) {
    if (!std::isfinite(s[k]))
      fail("state component " + state_names()[static_cast<std::size_t>(k)] + " is not finite");
  }
  for (int i = 0; i <= p_.trays; ++i) {
    const double m = s[2 * i + 1];
    const double xi = s[2 * i];
    if (m <= 0.0 || xi < -1e-6 || xi > 1.0 + 1e-6) {
      std::ostringstream msg;
      msg << (i == 0 ? std::string("reflux drum") : "tray " + std::to_string(i))
          << " left the physical range (M = " << m << " kmol, x = " << xi
          << ", expected M > 0, 0 ≤ x ≤ 1)";
      fail(msg.str());
    }
  }
  const Products pr = products(s, p_.nominal);
  if (pr.distillate_kmol_min < 0.0 || pr.bottoms_kmol_min < 0.0) {
    std::ostringstream msg;
    msg << "level loops demand negative product flows (D = " << pr.distillate_kmol_min
        << ", B = " << pr.bottoms_kmol_min << " kmol/min, expected ≥ 0)";
    fail(msg.str());
  }
  const double l_b = compartment_overflow(s);
  if (l_b < 0.0) {
    std::ostringstream msg;
    msg << "reboiler compartment runs dry (L_b = " << l_b << " kmol/min, expected ≥ 0)";
    fail(msg.str());
  }
}

void Pilot15::prepare() const {
  if (!work_) work_ = std::make_unique<Workspace>(*this);
}

void Pilot15::integrate(Eigen::VectorXd& s, const Operating& op, double duration_min,
                        StepMemory& steps, const Tolerance& tol, IntegrationStats* stats) const {
  validate(op, "pilot15 inputs");
  prepare();
  work_->system.set_operating(op);
  work_->stepper.integrate(work_->system, work_->solver, s, duration_min, steps, tol, stats);
  check_state(s);
}

}  // namespace excite::sim::column
