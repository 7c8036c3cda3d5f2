// SPDX-License-Identifier: MIT
#include "host/identify/gain_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/identify/element.hpp"

namespace excite::host {
namespace {

constexpr double kRoot = 1.96;  // the signed root √(ΔS/σ̂²) at the χ²₁ 95 % point
constexpr double kNear = 0.05;  // a walk point this close to kRoot (relative) ends the side
constexpr int kMaxSteps = 12;   // steps per side (each 1 to 8 times the last)
// A walk point this many σ̂² below the estimate's cost: the estimate is not the row's
// optimum (the convergence tests stop within 1e-4 σ̂² of one: bounded_lm.hpp).
constexpr double kBetter = 0.5;
constexpr double kInf = std::numeric_limits<double>::infinity();
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

class Walk {
 public:
  Walk(const RowProblem& row, const MisoResult& fit, int e)
      : row_(row), e_(e), S0_(row_cost(row, fit)) {
    sigma2_ = S0_ / std::max(row_dof(row, fit), 1.0);
    origin_ = {fit.elements[static_cast<std::size_t>(e)].value.gain, 0.0, gains_of(fit),
               values_of(fit)};
    // The linearised ridge: the regression of the row's gains on gain e (exact for a linear
    // model), where the covariance is known; else only gain e moves at first.
    const Eigen::MatrixXd& C = fit.gain_covariance;
    const double var = C(e, e);
    slope_ = Eigen::VectorXd::Unit(origin_.gains.size(), e);
    if (std::isfinite(var) && var > 0.0 && C.col(e).allFinite()) slope_ = C.col(e) / var;
    // The other start of each walk point (gain_profile.hpp): the element with the dynamics
    // of the row's largest response, |K|·‖u‖, as far as its own structure has them.
    const Eigen::Index largest = largest_response(row, fit);
    if (largest >= 0 && largest != e) {
      // In the element's own structure: the walk does not change structures (BIC chose it).
      const ElementModel& own = fit.elements[static_cast<std::size_t>(e)].value;
      alternative_ =
          with_structure(fit.elements[static_cast<std::size_t>(largest)].value, own.structure);
    }
    const double se = fit.elements[static_cast<std::size_t>(e)].std_error.gain;
    const double scale = std::max(origin_.gains.cwiseAbs().maxCoeff(), 1e-12);
    // The first step aims at the linearised bound, K̂ ± 1.96·SE: where the linearisation
    // holds, one point per side ends the walk.
    first_step_ = std::max(std::isfinite(se) && se > 0.0 ? kRoot * se : 0.01 * scale, 1e-3 * scale);
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
      if (std::abs(next.root - kRoot) <= kNear * kRoot) {
        bounded = true;
        return through(prev, next);
      }
      if (next.root >= kRoot) {
        bounded = true;
        // Once more at the signed root's linear interpolation (exact for a quadratic
        // profile), then the bracket that holds the bound, interpolated.
        const Point mid = at(prev, slope, through(prev, next).c);
        if (better_) break;
        return mid.root >= kRoot ? through(prev, mid) : through(mid, next);
      }
      // The signed root is linear in c for a quadratic profile: the next step aims a little
      // past where the last two points put the bound, at most 8 times the last step.
      const double rise = next.root - prev.root;
      const double aim = rise > 0.0 ? 1.2 * (kRoot - next.root) * step / rise : kInf;
      step = std::clamp(aim, step, 8.0 * step);
      prev = std::move(next);
    }
    return prev;
  }

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
    if (alternative_) {
      start[static_cast<std::size_t>(e_)] = *alternative_;
      start[static_cast<std::size_t>(e_)].gain = c;
      MisoResult g = held_fit(start, c);
      const double Sg = row_cost(row_, g);
      if (Sg < S) {
        f = std::move(g);
        S = Sg;
      }
    }
    if (S < S0_ - kBetter * sigma2_) {
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

  // The point where the signed root is kRoot on the line through a and b (a's root below
  // b's), between them or a little past b (its gains too).
  static Point through(const Point& a, const Point& b) {
    const double t =
        b.root > a.root ? std::clamp((kRoot - a.root) / (b.root - a.root), 0.0, 1.0 + kNear) : 1.0;
    return {a.c + t * (b.c - a.c), kRoot, a.gains + t * (b.gains - a.gains), a.values};
  }

  const RowProblem& row_;
  int e_;
  double S0_;
  double sigma2_ = 0.0;
  Point origin_;
  Eigen::VectorXd slope_;
  double first_step_ = 0.0;
  int fits_ = 0;
  std::optional<MisoResult> better_;
  std::optional<ElementModel> alternative_;
};

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
  GainInterval out;
  const Point low = walk.side(-1, out.lower_bounded);
  Point high = low;
  if (!walk.better()) high = walk.side(+1, out.upper_bounded);
  out.fits = walk.fits();
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
    est.std_error.gain = std::sqrt(C(i, i));
    est.covariance(kGain, kGain) = C(i, i);
    mark_weak_gain(est);
  }
}

void widen_along_ridge(MisoResult& fit, int e, const GainInterval& interval) {
  const double half = (interval.upper - interval.lower) / 2.0;
  add_gain_variance(fit, interval.ridge, half * half / (kRoot * kRoot) - fit.gain_covariance(e, e));
}

}  // namespace excite::host
