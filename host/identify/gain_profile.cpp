// SPDX-License-Identifier: MIT
#include "host/identify/gain_profile.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "host/identify/element.hpp"

namespace excite::host {
namespace {

constexpr double kRoot = 1.96;  // the signed root √(ΔS/σ̂²) at the χ²₁ 95 % point
constexpr double kNear = 0.05;  // a walk point this close to the bound (relative) ends the side
constexpr int kMaxSteps = 12;   // steps per side (each 1 to 8 times the last)
// A walk point this many σ̂² below the estimate's cost: the estimate is not the row's
// optimum (the convergence tests stop within 1e-4 σ̂² of one: bounded_lm.hpp).
constexpr double kBetter = 0.5;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A gain's SE widened along a projected ridge by less than this factor keeps K ± 1.96·SE.
constexpr double kMaterial = 1.01;
// Probes of a projection across zero (across_zero), at 1, 2, 4, … 128 times the scale.
constexpr int kAcrossZeroProbes = 8;
// At most this many restarts from a better optimum a walk found.
constexpr int kRestarts = 2;
// A row whose residual is this small a part of its output (in squares: an rms of 1e-10 of
// the output's, below any converter's resolution) is fitted to rounding: its gains are
// exact and a walk's cost differences are rounding noise (a noise-free twoweak4x4 run's rows
// end at 1e-29 to 1e-25, and their walks found "better" optima at 1e-12 of the gain).
constexpr double kRounding = 1e-20;

// A point of the walk: the held value, its signed root and the row's gains there.
struct Point {
  double c = 0.0;
  double root = 0.0;
  Eigen::VectorXd gains;
  std::vector<ElementModel> values;
};

// The χ²₁ profile (profile_gain), or the projection of an element's joint region
// (projected_gain_interval).
enum class WalkKind { profile, projection };

// The slowest lag of the row's estimated elements (T_p1, T_p2, T_n), 0 when none has one.
double slowest_lag(const MisoResult& fit) {
  double slowest = 0.0;
  for (const ElementEstimate& est : fit.elements) {
    if (!est.estimated()) continue;
    for (const int k : {kTp1, kTp2, kNatural}) {
      if (is_free(est.value.structure, k)) slowest = std::max(slowest, est.value[k]);
    }
  }
  return slowest;
}

class Walk {
 public:
  // A profile walks to the signed root kRoot and stops at a point that fits better than the
  // estimate (better()). A projection walks to √χ²_p (p the element's free parameters); a
  // point that fits better counts as inside (root 0) and the walk goes on, the bound staying
  // χ² above the estimate's cost, not the better point's (which can only widen the interval);
  // and each point is also fitted from slow dynamics (the other sign's basin of a small
  // element sits there: across_zero).
  Walk(const RowProblem& row, const MisoResult& fit, int e, WalkKind kind = WalkKind::profile)
      : row_(row), e_(e), S0_(row_cost(row, fit)), kind_(kind) {
    const ElementModel& own = fit.elements[static_cast<std::size_t>(e)].value;
    root_ = kind == WalkKind::profile
                ? kRoot
                : std::sqrt(chi_square_95(static_cast<int>(free_parameters(own.structure).size())));
    sigma2_ = S0_ / std::max(row_dof(row, fit), 1.0);
    origin_ = {own.gain, 0.0, gains_of(fit), values_of(fit)};
    // The linearised ridge: the regression of the row's gains on gain e (exact for a linear
    // model), where the covariance is known; else only gain e moves at first.
    const Eigen::MatrixXd& C = fit.gain_covariance;
    const double var = C(e, e);
    slope_ = Eigen::VectorXd::Unit(origin_.gains.size(), e);
    if (std::isfinite(var) && var > 0.0 && C.col(e).allFinite()) slope_ = C.col(e) / var;
    // The other start of each walk point (gain_profile.hpp): the element with the dynamics
    // of the row's largest response, |K|·‖u‖, as far as its own structure has them. In the
    // element's own structure: the walk does not change structures (BIC chose it).
    const Eigen::Index largest = largest_response(row, fit);
    if (largest >= 0 && largest != e) {
      alternatives_.push_back(
          with_structure(fit.elements[static_cast<std::size_t>(largest)].value, own.structure));
    }
    // A projection's slow start: the element's own delay, its slowest lag twice the row's.
    if (kind == WalkKind::projection && slowest_lag(fit) > 0.0) {
      ElementModel slow = own;
      for (const int k : {kTp1, kNatural}) {
        if (is_free(own.structure, k))
          slow[k] = std::min(2.0 * slowest_lag(fit), row.bounds.max_time_constant_min);
      }
      alternatives_.push_back(slow);
    }
    const double se = fit.elements[static_cast<std::size_t>(e)].std_error.gain;
    const double scale = std::max(origin_.gains.cwiseAbs().maxCoeff(), 1e-12);
    // The first step aims at the linearised bound, K̂ ± root·SE: where the linearisation
    // holds, one point per side ends the walk.
    first_step_ = std::max(std::isfinite(se) && se > 0.0 ? root_ * se : 0.01 * scale, 1e-3 * scale);
  }

  // Walks to one side (+1 or −1); the end point, interpolated to the χ² bound when reached.
  // Sets better_ and returns early when a point fits better than the estimate.
  Point side(int direction, bool& bounded) {
    Point prev = origin_;
    Eigen::VectorXd slope = slope_;
    double step = first_step_;
    bounded = false;
    for (int k = 0; k < kMaxSteps && !better_; ++k) {
      Point next = at(prev, slope, prev.c + direction * step);
      if (better_) break;
      slope = (next.gains - prev.gains) / (next.c - prev.c);
      // A point within kNear of the bound: the bound, on the line through it and the last.
      if (std::abs(next.root - root_) <= kNear * root_) {
        bounded = true;
        return through(prev, next);
      }
      if (next.root >= root_) {
        bounded = true;
        // Once more at the signed root's linear interpolation (exact for a quadratic
        // profile), then the bracket that holds the bound, interpolated.
        const Point mid = at(prev, slope, through(prev, next).c);
        if (better_) break;
        return mid.root >= root_ ? through(prev, mid) : through(mid, next);
      }
      // The signed root is linear in c for a quadratic profile: the next step aims a little
      // past where the last two points put the bound, at most 8 times the last step.
      const double rise = next.root - prev.root;
      const double aim = rise > 0.0 ? 1.2 * (root_ - next.root) * step / rise : kInf;
      step = std::clamp(aim, step, 8.0 * step);
      prev = std::move(next);
    }
    return prev;
  }

  // The row refitted with gain e held at c, from the estimate's values (and from each
  // alternative start): a probe away from the walk.
  Point probe(double c) { return at(origin_, Eigen::VectorXd::Zero(origin_.gains.size()), c); }
  double root() const { return root_; }

  int fits() const { return fits_; }
  const std::optional<MisoResult>& better() const { return better_; }
  std::optional<MisoResult>& better() { return better_; }

 private:
  // The row refitted with gain e held at c, started from `from` moved along `slope`.
  Point at(const Point& from, const Eigen::VectorXd& slope, double c) {
    std::vector<ElementModel> start = from.values;
    for (std::size_t a = 0; a < start.size(); ++a) {
      start[a].gain = from.gains(static_cast<Eigen::Index>(a)) +
                      slope(static_cast<Eigen::Index>(a)) * (c - from.c);
    }
    start[static_cast<std::size_t>(e_)].gain = c;
    MisoResult f = held_fit(start, c);
    double S = row_cost(row_, f);
    for (const ElementModel& alternative : alternatives_) {
      start[static_cast<std::size_t>(e_)] = alternative;
      start[static_cast<std::size_t>(e_)].gain = c;
      MisoResult g = held_fit(start, c);
      const double Sg = row_cost(row_, g);
      if (Sg < S) {
        f = std::move(g);
        S = Sg;
      }
    }
    if (kind_ == WalkKind::profile && S < S0_ - kBetter * sigma2_) {
      // Polished free from there, with standard errors, for the caller to keep.
      better_ = fit_miso(row_.U, row_.y, row_.inputs, values_of(f), row_.T_min, row_.bounds,
                         row_.max_iterations, row_.layout, row_.trend);
      ++fits_;
    }
    return {c, std::sqrt(std::max(S - S0_, 0.0) / sigma2_), gains_of(f), values_of(f)};
  }

  MisoResult held_fit(const std::vector<ElementModel>& start, double c) {
    ++fits_;
    return fit_miso(row_.U, row_.y, row_.inputs, start, row_.T_min, row_.bounds,
                    row_.max_iterations, row_.layout, row_.trend, LmOptions{}.cost_tolerance,
                    MisoUncertainty::none, HeldGain{e_, c});
  }

  // The point where the signed root is root_ on the line through a and b (a's root below
  // b's), between them or a little past b (its gains too).
  Point through(const Point& a, const Point& b) const {
    const double t =
        b.root > a.root ? std::clamp((root_ - a.root) / (b.root - a.root), 0.0, 1.0 + kNear) : 1.0;
    return {a.c + t * (b.c - a.c), root_, a.gains + t * (b.gains - a.gains), a.values};
  }

  const RowProblem& row_;
  int e_;
  double S0_;
  WalkKind kind_;
  double root_ = kRoot;
  double sigma2_ = 0.0;
  Point origin_;
  Eigen::VectorXd slope_;
  double first_step_ = 0.0;
  int fits_ = 0;
  std::optional<MisoResult> better_;
  std::vector<ElementModel> alternatives_;
};

// Gain e's profile walked to the walk's signed root on each side.
GainInterval walked(Walk& walk, int e) {
  GainInterval out;
  const Point low = walk.side(-1, out.lower_bounded);
  Point high = low;
  if (!walk.better()) high = walk.side(+1, out.upper_bounded);
  out.fits = walk.fits();
  out.root = walk.root();
  if (walk.better()) {
    out.better = std::move(walk.better());
    return out;
  }
  out.lower = low.c;
  out.upper = high.c;
  out.ridge = Eigen::VectorXd::Unit(low.gains.size(), e);
  if (high.c > low.c) out.ridge = (high.gains - low.gains) / (high.c - low.c);
  return out;
}

// A walked interval extended across zero where the region has a part of its own on the
// other side (projected_gain_interval; at K = 0 the element adds nothing, and the cost can
// rise there between two basins of either sign): probes at c = −sign(K̂)·2^k·max(|K̂|, SE),
// k = 0, 1, …, beyond the walk's end on that side, until one is outside after one inside, or,
// before any is inside, one outside no nearer the bound than the probe before it (at most
// kAcrossZeroProbes). The interval is taken to the farthest probe inside, interpolated
// towards the first outside after it (unbounded where the last probe is inside).
void across_zero(Walk& walk, const ElementEstimate& est, GainInterval& out) {
  const double K = est.value.gain;
  const double direction = K > 0.0 ? -1.0 : 1.0;
  const double end = direction < 0.0 ? out.lower : out.upper;
  const double scale = std::max(std::abs(K), est.std_error.gain);
  std::optional<Point> inside;
  bool bounded = true;
  double last_root = kInf;
  for (int k = 0; k < kAcrossZeroProbes; ++k) {
    const double c = direction * scale * std::ldexp(1.0, k);
    if (direction * (c - end) <= 0.0) continue;  // within the walked interval
    const Point p = walk.probe(c);
    if (p.root <= walk.root()) {
      inside = p;
      bounded = k + 1 < kAcrossZeroProbes;
      continue;
    }
    if (inside) {
      const double t = std::clamp((walk.root() - inside->root) / (p.root - inside->root), 0.0, 1.0);
      inside->c += t * (p.c - inside->c);
      break;
    }
    if (p.root >= last_root) break;  // the cost rises away from zero: no part there
    last_root = p.root;
  }
  out.fits = walk.fits();
  if (!inside) return;
  if (direction < 0.0) {
    out.lower = std::min(out.lower, inside->c);
    out.lower_bounded = bounded;
  } else {
    out.upper = std::max(out.upper, inside->c);
    out.upper_bounded = bounded;
  }
}

}  // namespace

double row_cost(const RowProblem& row, const MisoResult& fit) {
  return (row.y - fit.y_hat).cwiseProduct(row.layout.weight).squaredNorm();
}

double row_dof(const RowProblem& row, const MisoResult& fit) {
  Eigen::Index P = 0;
  for (const ElementEstimate& e : fit.elements) {
    P += static_cast<Eigen::Index>(free_parameters(e.value.structure).size());
  }
  return static_cast<double>(row.layout.scored() - row.trend.cols() - P);
}

GainInterval profile_gain(const RowProblem& row, const MisoResult& fit, int e) {
  Walk walk(row, fit, e);
  return walked(walk, e);
}

double chi_square_95(int p) {
  // The 95 % points of χ²_p, p = 1…7 (Abramowitz and Stegun 1964, table 26.8).
  static constexpr std::array<double, 7> kPoints{3.841,  5.991,  7.815, 9.488,
                                                 11.070, 12.592, 14.067};
  if (p < 1 || p > static_cast<int>(kPoints.size())) {
    throw std::invalid_argument("chi-square degrees of freedom = " + std::to_string(p) +
                                ", expected 1 to 7 (an element's free parameters)");
  }
  return kPoints[static_cast<std::size_t>(p - 1)];
}

Eigen::Index largest_response(const RowProblem& row, const MisoResult& fit) {
  Eigen::Index largest = -1;
  double largest_part = -1.0;
  for (std::size_t a = 0; a < fit.elements.size(); ++a) {
    const double part = std::abs(fit.elements[a].value.gain) * row.U.col(row.inputs[a]).norm();
    if (fit.elements[a].estimated() && part > largest_part) {
      largest_part = part;
      largest = static_cast<Eigen::Index>(a);
    }
  }
  return largest;
}

namespace {

// Whether the data leave an element's dynamics undetermined, its gain read from the fast part
// of the response: the delay on its upper bound, the main lag (T_p1, or T_n) shorter than a
// sample (a gain and a delay: the fast basin), or ζ on its lower bound (a resonance the data
// do not damp). A delay at 0, a second lag at 0 or two equal lags (their split without an SE)
// are an element simpler than its structure, its gain determined.
bool undetermined_dynamics(const ElementEstimate& est, double T_min) {
  const auto bound = [&](int k) { return est.at_bound[static_cast<std::size_t>(k)]; };
  const Structure s = est.value.structure;
  const int lag = is_free(s, kTp1) ? kTp1 : kNatural;
  return bound(kDelay) == Bound::upper || (is_free(s, lag) && est.value[lag] < T_min) ||
         (is_free(s, kDamping) && bound(kDamping) == Bound::lower);
}

}  // namespace

std::string projection_needed(const ElementEstimate& est, double T_min) {
  const char* const undetermined =
      "projected from its joint 95 % region: its dynamics are not determined";
  const double se = est.std_error.gain;
  if (!est.estimated() || !(se > 0.0)) return "";
  // An infinite SE: a direction the output does not depend on runs through K (miso_fit.hpp),
  // and K ± 1.96·SE says nothing. The projection is then the only interval the gain gets.
  if (std::isinf(se)) return undetermined;
  const auto p = static_cast<int>(free_parameters(est.value.structure).size());
  if (std::abs(est.value.gain) < std::sqrt(chi_square_95(p)) * se)
    return "projected from its joint 95 % region, which reaches K = 0";
  if (undetermined_dynamics(est, T_min)) return undetermined;
  return "";
}

namespace {

// Element e's projection on the row's fit as it is: its region walked, and across zero where
// the walk ended bounded on that side.
GainInterval projection_in_fit(const RowProblem& row, const MisoResult& fit, int e) {
  const ElementEstimate& est = fit.elements[static_cast<std::size_t>(e)];
  Walk walk(row, fit, e, WalkKind::projection);
  GainInterval out = walked(walk, e);
  if (est.value.gain > 0.0 ? out.lower_bounded : out.upper_bounded) across_zero(walk, est, out);
  return out;
}

// The row refitted with first-order element e in two lags (each half its lag, its delay
// kept), with standard errors: the structure one lag richer, which nests its own.
MisoResult fit_in_two_lags(const RowProblem& row, const MisoResult& fit, int e) {
  std::vector<ElementModel> start = values_of(fit);
  ElementModel& own = start[static_cast<std::size_t>(e)];
  const double lag = std::max(own[kTp1] / 2.0, row.T_min);
  own = with_structure(own, Structure::two_poles);
  own[kTp1] = own[kTp2] = lag;
  return fit_miso(row.U, row.y, row.inputs, start, row.T_min, row.bounds, row.max_iterations,
                  row.layout, row.trend);
}

}  // namespace

std::optional<GainInterval> projected_gain_interval(const RowProblem& row, const MisoResult& fit,
                                                    int e, ProjectionScope scope) {
  const ElementEstimate& est = fit.elements.at(static_cast<std::size_t>(e));
  if (projection_needed(est, row.T_min).empty()) return std::nullopt;
  if (row_cost(row, fit) <= kRounding * row.y.cwiseProduct(row.layout.weight).squaredNorm())
    return std::nullopt;
  GainInterval out = projection_in_fit(row, fit, e);
  if (scope != ProjectionScope::fit_is_final || est.value.structure != Structure::first_order)
    return out;
  const MisoResult lags = fit_in_two_lags(row, fit, e);
  if (!lags.elements[static_cast<std::size_t>(e)].estimated()) return out;
  const GainInterval in_lags = projection_in_fit(row, lags, e);
  out.fits += in_lags.fits + 1;
  if (in_lags.lower < out.lower) {
    out.lower = in_lags.lower;
    out.lower_bounded = in_lags.lower_bounded;
  }
  if (in_lags.upper > out.upper) {
    out.upper = in_lags.upper;
    out.upper_bounded = in_lags.upper_bounded;
  }
  return out;
}

void project_gains_near_zero(const RowProblem& row, MisoResult& fit, ProjectionScope scope) {
  MisoResult widened = fit;  // the covariance the followers' intervals read
  std::vector<std::optional<GainBounds>> own(fit.elements.size());
  for (std::size_t e = 0; e < fit.elements.size(); ++e) {
    if (auto p = projected_gain_interval(row, fit, static_cast<int>(e), scope)) {
      own[e] = GainBounds{p->lower, p->upper};
      widen_along_ridge(widened, static_cast<int>(e), *p,
                        scope == ProjectionScope::fit_is_final ? kRoot : p->root);
    }
  }
  for (std::size_t e = 0; e < fit.elements.size(); ++e) {
    ElementEstimate& est = fit.elements[e];
    if (own[e]) {
      est.projected_gain = ProjectedGain{*own[e], projection_needed(est, row.T_min)};
      continue;
    }
    const double se = widened.elements[e].std_error.gain;
    if (!(se > kMaterial * est.std_error.gain)) continue;
    est.projected_gain =
        ProjectedGain{{est.value.gain - kRoot * se, est.value.gain + kRoot * se},
                      "widened with the row's projected gain, which the data tie it to"};
  }
}

MisoResult profile_gains(const RowProblem& row, MisoResult fit, const ProfileChoice& profiled) {
  if (row_cost(row, fit) <= kRounding * row.y.cwiseProduct(row.layout.weight).squaredNorm())
    return fit;
  for (int restart = 0;; ++restart) {
    MisoResult widened = fit;
    bool restarted = false;
    for (std::size_t e = 0; e < fit.elements.size() && !restarted; ++e) {
      if (!fit.elements[e].estimated() || !profiled(fit, static_cast<int>(e))) continue;
      GainInterval interval = profile_gain(row, fit, static_cast<int>(e));
      if (interval.better) {
        if (restart == kRestarts) continue;  // this gain keeps its linearised interval
        const int iterations = fit.iterations;
        fit = std::move(*interval.better);
        fit.iterations += iterations;
        restarted = true;
      } else {
        widen_along_ridge(widened, static_cast<int>(e), interval);
      }
    }
    if (!restarted) return widened;
  }
}

bool poorly_determined(const ElementEstimate& e) {
  return e.estimated() && std::isfinite(e.std_error.gain) &&
         e.std_error.gain > kPoorlyDetermined * std::abs(e.value.gain);
}

void add_gain_variance(MisoResult& fit, const Eigen::VectorXd& direction, double alpha) {
  if (!(alpha > 0.0) || !direction.allFinite()) return;
  Eigen::MatrixXd& C = fit.gain_covariance;
  C += alpha * direction * direction.transpose();
  for (std::size_t a = 0; a < fit.elements.size(); ++a) {
    ElementEstimate& est = fit.elements[a];
    const auto i = static_cast<Eigen::Index>(a);
    if (!std::isfinite(C(i, i)) || !(C(i, i) > est.std_error.gain * est.std_error.gain)) continue;
    const double before = std::isfinite(est.std_error.gain) ? est.std_error.gain : 0.0;
    est.profile_variance += C(i, i) - before * before;
    est.std_error.gain = std::sqrt(C(i, i));
    est.covariance(kGain, kGain) = C(i, i);
    mark_weak_gain(est);
  }
}

void widen_along_ridge(MisoResult& fit, int e, const GainInterval& interval, double root) {
  const double half = (interval.upper - interval.lower) / 2.0;
  add_gain_variance(fit, interval.ridge, half * half / (root * root) - fit.gain_covariance(e, e));
}

}  // namespace excite::host
