// SPDX-License-Identifier: MIT
#include "host/identify/miso_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>

#include "host/identify/bounded_lm.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::span<double> span_of(Eigen::VectorXd& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}

// Where each element's free parameters (free_parameters(structure), in that order, K first)
// sit in the fit's parameter vector.
class ParameterMap {
 public:
  explicit ParameterMap(const std::vector<ElementModel>& elements) : templates_(elements) {
    Eigen::Index o = 0;
    for (const ElementModel& g : elements) {
      offset_.push_back(o);
      o += static_cast<Eigen::Index>(free_parameters(g.structure).size());
    }
    size_ = o;
  }
  Eigen::Index size() const { return size_; }
  Eigen::Index elements() const { return static_cast<Eigen::Index>(templates_.size()); }
  Eigen::Index offset(Eigen::Index e) const { return offset_[static_cast<std::size_t>(e)]; }
  std::span<const int> free(Eigen::Index e) const {
    return free_parameters(templates_[static_cast<std::size_t>(e)].structure);
  }
  // The element e of x (gain included).
  ElementModel element(const Eigen::VectorXd& x, Eigen::Index e) const {
    ElementModel g = templates_[static_cast<std::size_t>(e)];
    const std::span<const int> f = free(e);
    for (std::size_t k = 0; k < f.size(); ++k)
      g[f[k]] = x(offset(e) + static_cast<Eigen::Index>(k));
    return g;
  }
  ElementModel unit_element(const Eigen::VectorXd& x, Eigen::Index e) const {
    ElementModel g = element(x, e);
    g.gain = 1.0;
    return g;
  }
  double gain(const Eigen::VectorXd& x, Eigen::Index e) const { return x(offset(e)); }

 private:
  std::vector<ElementModel> templates_;
  std::vector<Eigen::Index> offset_;
  Eigen::Index size_ = 0;
};

// The row's simulation: unit-gain responses per element, scaled and summed; and its
// Jacobian by sensitivity filters (see jacobian()). Each element's discretisation is kept for
// the parameters it was last computed at: the Jacobian at an accepted step reuses the one
// its residual made (the same values: discretise() is a pure function).
class RowModel {
 public:
  RowModel(const Eigen::MatrixXd& U, const std::vector<int>& inputs, const ParameterMap& map,
           double T_min, const SampleLayout& layout)
      : U_(U),
        inputs_(inputs),
        map_(map),
        T_(T_min),
        layout_(layout),
        every_row_scored_((layout.weight.array() == 1.0).all()),
        W_(U.rows(), map.elements()),
        V_(U.rows(), map.elements()),
        first_lag_(static_cast<std::size_t>(map.elements())),
        base_(first_lag_.size()),
        poles_(first_lag_.size()),
        cache_(static_cast<std::size_t>(map.elements())),
        terms_(cache_.size()),
        gains_(cache_.size()),
        inputs_of_(cache_.size()) {}

  // Whether every row has weight 1 (multiplying by the weights would change nothing).
  bool every_row_scored() const { return every_row_scored_; }

  std::span<const double> input(Eigen::Index e) const {
    const auto col = U_.col(inputs_[static_cast<std::size_t>(e)]);
    return {col.data(), static_cast<std::size_t>(col.size())};
  }

  Eigen::VectorXd output(const Eigen::VectorXd& x) {
    Eigen::VectorXd y_hat(U_.rows());
    for (Eigen::Index e = 0; e < map_.elements(); ++e) {
      const auto i = static_cast<std::size_t>(e);
      terms_[i] = &discretised(e, map_.unit_element(x, e));
      gains_[i] = map_.gain(x, e);
      inputs_of_[i] = input(e);
    }
    simulate_sum_segments(terms_, gains_, inputs_of_, span_of(y_hat), layout_.segments, delayed_);
    return y_hat;
  }

  // ∂ŷ/∂x. With G = B(q)/D(q) (taps b_m by lag, D = 1 + a1 q⁻¹ + a2 q⁻² + a3 q⁻³), w = u/D and
  // v = z/D for the unit response z = B w:
  //   ∂z/∂θ = Σ_m (∂b_m/∂θ) w(k − m) − Σ_i (∂a_i/∂θ) v(k − i),
  // exact filters, each segment from rest (segments.hpp); only the scalar coefficient derivatives
  // are taken by central differences (one-sided on a bound), over a tap window wide enough for d to
  // change by one.
  void jacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                const Eigen::VectorXd& upper, Eigen::MatrixXd& J) {
    const Eigen::Index N = U_.rows();
    const Eigen::Index E = map_.elements();
    const std::vector<Segment>& segs = layout_.segments;
    J.resize(N, x.size());
    // Taps by lag from each element's own whole-sample delay minus one, so a perturbed delay
    // that crosses a sample boundary still fits the window. W = u / D, the elements side by side.
    for (Eigen::Index e = 0; e < E; ++e) {
      const auto i = static_cast<std::size_t>(e);
      const sim::DiscreteTerm& c = discretised(e, map_.unit_element(x, e));
      first_lag_[i] = static_cast<std::size_t>(std::max(c.delay_samples - 1, 0));
      base_[i] = lag_taps(c, first_lag_[i]);
      poles_[i] = base_[i].a;
      const std::span<const double> u = input(e);
      std::copy(u.begin(), u.end(), W_.col(e).data());
    }
    all_pole_filter_columns(poles_, W_, segs);
    // z = B w in K's column (every structure's first parameter), and V = z / D.
    for (Eigen::Index e = 0; e < E; ++e) {
      const auto i = static_cast<std::size_t>(e);
      terms_of_column_.clear();
      for (std::size_t t = 0; t < kLagWindow; ++t) {
        if (base_[i].b[t] != 0.0) {
          terms_of_column_.push_back(
              {base_[i].b[t], W_.col(e).data(), static_cast<Eigen::Index>(first_lag_[i] + t)});
        }
      }
      lagged_sum(J.col(map_.offset(e)), terms_of_column_, segs);
      V_.col(e) = J.col(map_.offset(e));
    }
    all_pole_filter_columns(poles_, V_, segs);
    for (Eigen::Index e = 0; e < E; ++e) derivative_columns(x, lower, upper, e, J);
    // Rows outside the cost have no residual, hence no sensitivity.
    if (!every_row_scored_) J.array().colwise() *= layout_.weight.array();
  }

 private:
  // ∂ŷ/∂θ of element e's parameters after K, from its W and V columns (jacobian()).
  void derivative_columns(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                          const Eigen::VectorXd& upper, Eigen::Index e, Eigen::MatrixXd& J) {
    const auto i = static_cast<std::size_t>(e);
    const Eigen::Index o = map_.offset(e);
    const ElementModel g = map_.unit_element(x, e);
    const double K = map_.gain(x, e);
    const std::size_t m0 = first_lag_[i];
    const std::span<const int> free = map_.free(e);
    for (std::size_t k = 1; k < free.size(); ++k) {
      const int m = free[k];
      const Eigen::Index col_index = o + static_cast<Eigen::Index>(k);
      const double val = x(col_index);
      const double h = 1e-6 * std::max(std::abs(val), m == kDamping ? 1.0 : T_);
      const double hi = std::min(val + h, upper(col_index));
      const double lo = std::max(val - h, lower(col_index));
      ElementModel gp = g;
      ElementModel gm = g;
      gp[m] = hi;
      gm[m] = lo;
      LagTaps tp;
      LagTaps tm;
      try {
        tp = lag_taps(gp, T_, m0);
        tm = lag_taps(gm, T_, m0);
      } catch (const std::invalid_argument&) {
        J.col(col_index).setZero();  // a neighbour the discretisation cannot take: held
        continue;
      }
      const double scale = K / (hi - lo);
      terms_of_column_.clear();
      for (std::size_t t = 0; t < kLagWindow; ++t) {
        const double db = scale * (tp.b[t] - tm.b[t]);
        if (db != 0.0)
          terms_of_column_.push_back({db, W_.col(e).data(), static_cast<Eigen::Index>(m0 + t)});
      }
      for (std::size_t p = 0; p < kMaxPoles; ++p) {
        const double da = scale * (tp.a[p] - tm.a[p]);
        if (da != 0.0)
          terms_of_column_.push_back({-da, V_.col(e).data(), static_cast<Eigen::Index>(p + 1)});
      }
      lagged_sum(J.col(col_index), terms_of_column_, layout_.segments);
    }
  }

  // discretise(g, T) for element e, from the cache when g is the element it was last made for.
  const sim::DiscreteTerm& discretised(Eigen::Index e, const ElementModel& g) {
    Cached& c = cache_[static_cast<std::size_t>(e)];
    if (!c.valid || !same_element(c.element, g)) {
      c.term = discretise(g, T_);  // throws before the cache changes
      c.element = g;
      c.valid = true;
    }
    return c.term;
  }
  static bool same_element(const ElementModel& a, const ElementModel& b) {
    if (a.structure != b.structure) return false;
    for (int p = 0; p < kParameters; ++p) {
      if (!(a[p] == b[p])) return false;
    }
    return true;
  }

  struct Cached {
    bool valid = false;
    ElementModel element;
    sim::DiscreteTerm term;
  };
  const Eigen::MatrixXd& U_;
  const std::vector<int>& inputs_;
  const ParameterMap& map_;
  double T_;
  const SampleLayout& layout_;
  bool every_row_scored_;
  // jacobian()'s scratch, a column per element: W = u / D, V = z / D, the taps' window.
  Eigen::MatrixXd W_;
  Eigen::MatrixXd V_;
  std::vector<std::size_t> first_lag_;
  std::vector<LagTaps> base_;
  std::vector<std::array<double, kMaxPoles>> poles_;
  std::vector<LaggedTerm> terms_of_column_;
  std::vector<Cached> cache_;
  // output()'s scratch: each element's term, gain and input, and the delayed inputs.
  std::vector<const sim::DiscreteTerm*> terms_;
  std::vector<double> gains_;
  std::vector<std::span<const double>> inputs_of_;
  std::vector<double> delayed_;
};

// A parameter whose squared component in a numerically null direction of JᵀJ exceeds this
// is not determined (inf). Below it the direction does not involve the parameter: a null
// direction such as T_d against a vanishing T_p2 is tilted by ~1e-5 towards other
// parameters (K of the same row: a weight ~1e-9), which must not make K undetermined.
constexpr double kNullWeight = 1e-6;

struct ParameterUncertainty {
  Eigen::VectorXd se;   // 1σ per parameter
  Eigen::MatrixXd cov;  // σ̂² (JᵀJ)⁺ over the determined directions; NaN rows/columns on a
                        // bound
};

// 1σ standard errors σ̂ √diag((JᵀJ)⁻¹) over the parameters not on a bound; inf for
// parameters in a direction the data do not determine (a numerically zero eigenvalue,
// weight above kNullWeight); the other parameters' variances over the determined directions.
// The covariance is the same pseudo-inverse, whole: its diagonal is se² except for an
// undetermined parameter (se inf), whose null direction it leaves out — the output does
// not change along that direction, so what the output determines stays finite.
ParameterUncertainty standard_errors(const Eigen::MatrixXd& J, Eigen::Index scored_rows, double sse,
                                     const std::vector<bool>& on_bound) {
  const Eigen::Index P = J.cols();
  ParameterUncertainty out{Eigen::VectorXd::Constant(P, kNaN),
                           Eigen::MatrixXd::Constant(P, P, kNaN)};
  Eigen::VectorXd& se = out.se;
  std::vector<Eigen::Index> free;
  for (Eigen::Index m = 0; m < P; ++m) {
    if (!on_bound[static_cast<std::size_t>(m)]) free.push_back(m);
  }
  const auto F = static_cast<Eigen::Index>(free.size());
  const Eigen::Index dof = scored_rows - F;
  if (F == 0 || dof <= 0) return out;
  Eigen::MatrixXd Jf(J.rows(), F);
  for (Eigen::Index a = 0; a < F; ++a) Jf.col(a) = J.col(free[static_cast<std::size_t>(a)]);
  // Scale columns to unit norm so the eigen test is about directions, not units.
  Eigen::VectorXd norms = Jf.colwise().norm().transpose();
  for (Eigen::Index a = 0; a < F; ++a) {
    if (norms(a) == 0.0) norms(a) = 1.0;
  }
  const Eigen::MatrixXd Js = Jf * norms.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Js.transpose() * Js);
  const Eigen::VectorXd& lam = eig.eigenvalues();
  const Eigen::MatrixXd& V = eig.eigenvectors();
  const double sigma2 = sse / static_cast<double>(dof);
  const double floor = 1e-13 * std::max(lam.maxCoeff(), 0.0);
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(F);  // 1/λ on the determined directions
  for (Eigen::Index k = 0; k < F; ++k) {
    if (lam(k) > floor) inverse(k) = 1.0 / lam(k);
  }
  const Eigen::MatrixXd cov_scaled = V * inverse.asDiagonal() * V.transpose();
  for (Eigen::Index a = 0; a < F; ++a) {
    for (Eigen::Index b = 0; b < F; ++b) {
      out.cov(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]) =
          sigma2 * cov_scaled(a, b) / (norms(a) * norms(b));
    }
  }
  for (Eigen::Index a = 0; a < F; ++a) {
    double var = 0.0;
    for (Eigen::Index k = 0; k < F; ++k) {
      const double w = V(a, k) * V(a, k);
      if (lam(k) <= floor) {
        if (w > kNullWeight) var = kInf;
      } else {
        var += w / lam(k);
      }
    }
    se(free[static_cast<std::size_t>(a)]) = std::sqrt(sigma2 * var) / norms(a);
  }
  return out;
}

}  // namespace

double natural_period_floor(double T_min) {
  return T_min / std::numbers::pi;
}

ParameterRange parameter_range(int parameter, const MisoBounds& bounds) {
  switch (parameter) {
    case kGain:
      return {-kInf, kInf};
    case kDelay:
      return {0.0, bounds.max_delay_min};
    case kZero:
      return {-bounds.max_time_constant_min, bounds.max_time_constant_min};
    case kDamping:
      return {kMinDamping, 1.0};
    case kNatural:
      return {bounds.min_natural_min, bounds.max_time_constant_min};
    default:
      return {0.0, bounds.max_time_constant_min};
  }
}

void mark_weak_gain(ElementEstimate& e) {
  const double k_se = e.std_error.gain;
  if (std::isfinite(k_se) ? std::abs(e.value.gain) < 2.0 * k_se : std::isinf(k_se)) {
    e.status = ElementStatus::weak_gain;
    char buf[220];
    std::snprintf(buf, sizeof buf,
                  "|K| = %.3g is below two standard errors (%.3g): the data barely show this "
                  "element, its delay and time constants are not determined",
                  std::abs(e.value.gain), k_se);
    e.reason = buf;
  }
}

namespace {

// The box of every free parameter (parameter_range), its typical size for the step test, and
// the start x0 from `initial`; the held gain, if any, pinned on a box of zero width.
Eigen::VectorXd box_and_start(const ParameterMap& map, const std::vector<ElementModel>& initial,
                              const MisoBounds& bounds, double T_min,
                              const std::optional<HeldGain>& held, LmProblem& problem) {
  const Eigen::Index P = map.size();
  problem.lower.resize(P);
  problem.upper.resize(P);
  problem.scale.resize(P);
  Eigen::VectorXd x0(P);
  for (Eigen::Index e = 0; e < map.elements(); ++e) {
    const ElementModel& g = initial[static_cast<std::size_t>(e)];
    const std::span<const int> free = map.free(e);
    for (std::size_t k = 0; k < free.size(); ++k) {
      const Eigen::Index i = map.offset(e) + static_cast<Eigen::Index>(k);
      const ParameterRange r = parameter_range(free[k], bounds);
      x0(i) = g[free[k]];
      problem.lower(i) = r.lower;
      problem.upper(i) = r.upper;
      problem.scale(i) = free[k] == kGain ? std::max(std::abs(g.gain), 1e-12)
                                          : (free[k] == kDamping ? 0.1 : T_min);
    }
  }
  if (held) {
    const Eigen::Index k = map.offset(held->element);
    x0(k) = problem.lower(k) = problem.upper(k) = held->value;
  }
  return x0;
}

// Element e of the fit at x: its values, standard errors, covariance and bounds reached,
// reported with T_p1 ≥ T_p2 (the model is symmetric in them), marked weak when |K| < 2 SE.
ElementEstimate element_estimate(const ParameterMap& map, Eigen::Index e, const Eigen::VectorXd& x,
                                 const LmProblem& problem, const std::vector<bool>& on_bound,
                                 const ParameterUncertainty& errors) {
  const Eigen::Index o = map.offset(e);
  const std::span<const int> free = map.free(e);
  ElementEstimate est;
  est.value = map.element(x, e);
  est.std_error = est.value;
  for (int k = 0; k < kParameters; ++k) est.std_error[k] = kNaN;
  for (std::size_t a = 0; a < free.size(); ++a) {
    const Eigen::Index ia = o + static_cast<Eigen::Index>(a);
    est.std_error[free[a]] = errors.se(ia);
    est.at_bound[static_cast<std::size_t>(free[a])] = !on_bound[static_cast<std::size_t>(ia)]
                                                          ? Bound::none
                                                      : x(ia) <= problem.lower(ia) ? Bound::lower
                                                                                   : Bound::upper;
    for (std::size_t b = 0; b < free.size(); ++b) {
      est.covariance(free[a], free[b]) = errors.cov(ia, o + static_cast<Eigen::Index>(b));
    }
  }
  if (is_free(est.value.structure, kTp2) && est.value.tau2_min > est.value.tau1_min) {
    std::swap(est.value.tau1_min, est.value.tau2_min);
    std::swap(est.std_error.tau1_min, est.std_error.tau2_min);
    std::swap(est.at_bound[kTp1], est.at_bound[kTp2]);
    est.covariance.row(kTp1).swap(est.covariance.row(kTp2));
    est.covariance.col(kTp1).swap(est.covariance.col(kTp2));
  }
  mark_weak_gain(est);
  return est;
}

}  // namespace

MisoResult fit_miso(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                    const std::vector<int>& inputs, std::vector<ElementModel> initial, double T_min,
                    const MisoBounds& bounds, int max_iterations, const SampleLayout& layout,
                    const Eigen::MatrixXd& trend, double cost_tolerance,
                    MisoUncertainty uncertainty, std::optional<HeldGain> held) {
  const ParameterMap map(initial);
  RowModel row(U, inputs, map, T_min, layout);
  const Eigen::Index m = map.elements();
  const Eigen::Index P = map.size();

  LmProblem problem;
  const Eigen::VectorXd x0 = box_and_start(map, initial, bounds, T_min, held, problem);
  // The simulation at the lowest cost evaluated so far: the minimiser's end (it accepts only
  // a lower cost), so the result's y_hat need not be simulated again.
  Eigen::VectorXd best_x;
  Eigen::VectorXd best_y_hat;
  double best_cost = kInf;
  problem.residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    Eigen::VectorXd y_hat;
    try {
      y_hat = row.output(x);
    } catch (const std::invalid_argument&) {
      return false;  // parameters the exact discretisation cannot take (poles ≪ T): a
                     // rejected step
    }
    if (row.every_row_scored()) {
      r = y - y_hat;
    } else {
      r = layout.weight.cwiseProduct(y - y_hat);
    }
    if (trend.cols() > 0) r -= trend * (trend.transpose() * r);
    const double cost = r.squaredNorm();
    if (cost < best_cost) {
      best_cost = cost;
      best_x = x;
      best_y_hat.swap(y_hat);
    }
    return true;
  };
  problem.jacobian = [&](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    row.jacobian(x, problem.lower, problem.upper, J);
    if (trend.cols() > 0) J -= trend * (trend.transpose() * J);
  };
  LmOptions lm_options;
  lm_options.max_iterations = max_iterations;
  lm_options.cost_tolerance = cost_tolerance;
  const LmResult lm = minimise_bounded(problem, x0, lm_options);

  MisoResult out;
  out.iterations = lm.iterations;
  out.converged = lm.converged;
  const bool simulated = best_x.size() == lm.x.size() && (best_x.array() == lm.x.array()).all();
  out.y_hat = simulated ? std::move(best_y_hat) : row.output(lm.x);
  if (trend.cols() > 0) {
    out.y_hat += trend * (trend.transpose() * layout.weight.cwiseProduct(y - out.y_hat));
  }
  std::vector<bool> on_bound(static_cast<std::size_t>(P));
  for (Eigen::Index k = 0; k < P; ++k) {
    on_bound[static_cast<std::size_t>(k)] =
        lm.x(k) <= problem.lower(k) || lm.x(k) >= problem.upper(k);
  }
  ParameterUncertainty errors{Eigen::VectorXd::Constant(P, kNaN),
                              Eigen::MatrixXd::Constant(P, P, kNaN)};
  if (uncertainty == MisoUncertainty::standard_errors) {
    Eigen::MatrixXd J;
    problem.jacobian(lm.x, J);
    errors = standard_errors(J, layout.scored() - trend.cols(), lm.cost, on_bound);
  }
  out.gain_covariance.resize(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) {
      out.gain_covariance(a, b) = errors.cov(map.offset(a), map.offset(b));
    }
  }

  for (Eigen::Index e = 0; e < m; ++e) {
    out.elements.push_back(element_estimate(map, e, lm.x, problem, on_bound, errors));
  }
  return out;
}

Eigen::VectorXd gains_of(const MisoResult& fit) {
  Eigen::VectorXd K(static_cast<Eigen::Index>(fit.elements.size()));
  for (std::size_t a = 0; a < fit.elements.size(); ++a)
    K(static_cast<Eigen::Index>(a)) = fit.elements[a].value.gain;
  return K;
}

Eigen::VectorXd gain_errors_of(const MisoResult& fit) {
  Eigen::VectorXd se(static_cast<Eigen::Index>(fit.elements.size()));
  for (std::size_t a = 0; a < fit.elements.size(); ++a)
    se(static_cast<Eigen::Index>(a)) = fit.elements[a].std_error.gain;
  return se;
}

std::vector<ElementModel> values_of(const MisoResult& fit) {
  std::vector<ElementModel> v;
  for (const ElementEstimate& e : fit.elements) v.push_back(e.value);
  return v;
}

}  // namespace excite::host
