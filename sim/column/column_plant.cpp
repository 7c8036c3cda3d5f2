// SPDX-License-Identifier: MIT
#include "sim/column/column_plant.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sim/column/cola_a.hpp"
#include "sim/column/pilot15.hpp"
#include "sim/column/steady_state.hpp"

namespace excite::sim::column {
namespace {

Operating with_inputs(Operating op, const double* u, const Operating& nominal) {
  op.reflux_kmol_min = nominal.reflux_kmol_min + u[0];
  op.boilup_kmol_min = nominal.boilup_kmol_min + u[1];
  return op;
}

void require_finite_inputs(const double* u, const std::string& plant, long row) {
  for (int i = 0; i < 2; ++i) {
    if (std::isfinite(u[i])) continue;
    std::ostringstream msg;
    msg << plant << ": input " << (i == 0 ? "L" : "V") << " deviation";
    if (row >= 0) msg << " at sample " << row;
    msg << " is " << u[i] << ", expected a finite number (kmol/min)";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

Eigen::MatrixXd Linearisation::static_gain() const {
  return -c * a.partialPivLu().solve(b);
}

ColumnPlant::ColumnPlant(std::unique_ptr<ColumnModel> model)
    : model_(std::move(model)), input_context_(model_->name() + " inputs (nominal + deviation)") {
  const Operating nom = model_->nominal();
  nominal_state_ = solve_steady_state(*model_, nom, model_->initial_guess(nom)).state;
  const Products p = model_->products(nominal_state_, nom);
  nominal_y_ = Eigen::Vector2d(p.x_top, p.x_bottom);
  nominal_linearisation_ = linearise(nominal_state_, nom);
  reset();
}

ColumnPlant ColumnPlant::cola_a() {
  return ColumnPlant(std::make_unique<ColaA>());
}
ColumnPlant ColumnPlant::pilot15() {
  return ColumnPlant(std::make_unique<Pilot15>());
}

ColumnPlant ColumnPlant::by_name(const std::string& name) {
  if (name == "colaA") return cola_a();
  if (name == "pilot15") return pilot15();
  throw std::invalid_argument("unknown column plant \"" + name +
                              "\", expected \"colaA\" or \"pilot15\"");
}

Linearisation ColumnPlant::linearise(const Eigen::VectorXd& state, const Operating& op) const {
  validate(op, model_->name() + " linearisation");
  Linearisation lin;
  lin.a = model_->jacobian(state, op);
  const Eigen::Index n = model_->state_size();
  lin.b.resize(n, 2);
  Eigen::VectorXd up(n), down(n);
  for (int i = 0; i < 2; ++i) {
    Operating hi = op, lo = op;
    double& h_in = i == 0 ? hi.reflux_kmol_min : hi.boilup_kmol_min;
    double& l_in = i == 0 ? lo.reflux_kmol_min : lo.boilup_kmol_min;
    const double h = 1e-6 * std::max(1.0, std::abs(h_in));
    h_in += h;
    l_in -= h;
    model_->derivative(state, hi, up);
    model_->derivative(state, lo, down);
    lin.b.col(i) = (up - down) / (2.0 * h);
  }
  // C = ∂(x_D, x_B)/∂s by central differences (x_D, x_B are state components or, for
  // pilot15's sump, m_B/M_B).
  lin.c = Eigen::MatrixXd::Zero(2, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double h = 1e-7 * std::max(1.0, std::abs(state[k]));
    Eigen::VectorXd sp = state, sm = state;
    sp[k] += h;
    sm[k] -= h;
    const Products pp = model_->products(sp, op);
    const Products pm = model_->products(sm, op);
    lin.c(0, k) = (pp.x_top - pm.x_top) / (2.0 * h);
    lin.c(1, k) = (pp.x_bottom - pm.x_bottom) / (2.0 * h);
  }
  return lin;
}

Eigen::VectorXd ColumnPlant::steady_state(const Operating& op) const {
  return solve_steady_state(*model_, op, nominal_state_).state;
}

void ColumnPlant::set_disturbances(double feed_kmol_min, double feed_light) {
  Operating op = disturbance_;
  op.feed_kmol_min = feed_kmol_min;
  op.feed_light = feed_light;
  validate(op, model_->name() + " disturbances");
  disturbance_ = op;
}

void ColumnPlant::reset() {
  state_ = nominal_state_;
  trial_ = nominal_state_;
  disturbance_ = model_->nominal();
  steps_ = {};
  stats_ = {};
  samples_ = 0;
  model_->prepare();
}

void ColumnPlant::set_max_steps_per_sample(long n) {
  if (n < 1) {
    std::ostringstream msg;
    msg << model_->name() << ": max_steps_per_sample = " << n << ", expected at least 1";
    throw std::invalid_argument(msg.str());
  }
  tol_.max_steps = n;
}

void ColumnPlant::set_state(const Eigen::VectorXd& s) {
  if (s.size() != model_->state_size()) {
    std::ostringstream msg;
    msg << model_->name() << ": state has " << s.size() << " components, expected "
        << model_->state_size();
    throw std::invalid_argument(msg.str());
  }
  model_->check_state(s);
  state_ = s;
}

void ColumnPlant::set_sample_time_min(double t) {
  if (!(std::isfinite(t) && t > 0.0)) {
    std::ostringstream msg;
    msg << model_->name() << ": sample time " << t << " min, expected a positive number";
    throw std::invalid_argument(msg.str());
  }
  sample_time_min_ = t;
}

Eigen::Vector2d ColumnPlant::output_deviation() const {
  const Products p = model_->products(state_, disturbance_);
  return Eigen::Vector2d(p.x_top, p.x_bottom) - nominal_y_;
}

void ColumnPlant::advance(const double* u, double duration_min, long sample) {
  const Operating op = with_inputs(disturbance_, u, model_->nominal());
  validate(op, input_context_);
  trial_ = state_;  // same size: no allocation
  StepMemory steps = steps_;
  try {
    model_->integrate(trial_, op, duration_min, steps, tol_, &stats_);
  } catch (const std::runtime_error& e) {
    std::ostringstream msg;
    msg << model_->name() << ": sample " << sample << " (" << duration_min
        << " min) needs more than max_steps_per_sample = " << tol_.max_steps
        << " integration steps, or the step size collapsed (" << e.what()
        << "); the plant stays at the start of the sample";
    throw std::runtime_error(msg.str());
  }
  state_.swap(trial_);  // only a completed interval is committed
  steps_ = steps;
  ++samples_;
}

Eigen::MatrixXd ColumnPlant::simulate(const Eigen::MatrixXd& U, double sample_time_min) {
  if (U.cols() != 2) {
    std::ostringstream msg;
    msg << model_->name() << ": input matrix has " << U.cols()
        << " columns, expected 2 (L, V deviations)";
    throw std::invalid_argument(msg.str());
  }
  if (!(std::isfinite(sample_time_min) && sample_time_min > 0.0)) {
    std::ostringstream msg;
    msg << model_->name() << ": sample time " << sample_time_min
        << " min, expected a positive number";
    throw std::invalid_argument(msg.str());
  }
  for (Eigen::Index k = 0; k < U.rows(); ++k) {
    const double u[2] = {U(k, 0), U(k, 1)};
    require_finite_inputs(u, model_->name(), static_cast<long>(k));
  }
  Eigen::MatrixXd Y(U.rows(), 2);
  for (Eigen::Index k = 0; k < U.rows(); ++k) {
    Y.row(k) = output_deviation().transpose();
    const double u[2] = {U(k, 0), U(k, 1)};
    advance(u, sample_time_min, static_cast<long>(k));
  }
  return Y;
}

void ColumnPlant::step(const double* u, double* y) {
  require_finite_inputs(u, model_->name(), samples_);
  const Eigen::Vector2d dy = output_deviation();
  y[0] = dy[0];
  y[1] = dy[1];
  advance(u, sample_time_min_, samples_);
}

}  // namespace excite::sim::column
