// SPDX-License-Identifier: MIT
#include "host/identify/structure_search.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "host/identify/gain_sensitivity.hpp"
#include "host/identify/residuals.hpp"

namespace excite::host {
namespace {

// Iterations of one element fitted alone to its part of the output (a trial, not the result).
constexpr int kTrialAloneIterations = 12;
// Rounds of changes per row.
constexpr int kRounds = 6;
// A delay within this many samples of a whole number is tried on the other side too.
constexpr double kDelayKink = 0.05;
// An element with |K| below this many standard errors is restarted from the other sign.
constexpr double kWeakRatio = 5.0;
// An element whose simulated part is below this share of its row's (by norm) is restarted too.
constexpr double kSmallShare = 0.05;
constexpr std::array<double, 2> kRestartScales{1.0, 0.25};
// Elements restarted on a row whose residual is not white (restart_misplaced_dynamics), the
// most dependent on their input first.
constexpr std::size_t kMisplacedRestarts = 2;
// A change of structure must lower the criterion by more than this: a BIC difference below 2
// is "not worth more than a bare mention" (Kass and Raftery 1995), so a structure that only
// equals another (an underdamped pair at ζ = 1 against two equal lags) does not replace it.
constexpr double kEvidence = 2.0;
// SSE floor relative to the output's energy (noise-free fits tie at rounding).
constexpr double kSseFloor = 1e-12;

Eigen::Index parameter_count(const std::vector<ElementEstimate>& elements) {
  Eigen::Index p = 0;
  for (const ElementEstimate& e : elements)
    p += static_cast<Eigen::Index>(free_parameters(e.value.structure).size());
  return p;
}
Eigen::Index parameter_count(const std::vector<ElementModel>& elements) {
  Eigen::Index p = 0;
  for (const ElementModel& g : elements)
    p += static_cast<Eigen::Index>(free_parameters(g.structure).size());
  return p;
}

double weighted_sse(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                    const SampleLayout& layout) {
  return (a - b).cwiseProduct(layout.weight).squaredNorm();
}

ElementModel clamped(ElementModel g, const MisoBounds& bounds) {
  for (const int k : free_parameters(g.structure)) {
    const ParameterRange r = parameter_range(k, bounds);
    g[k] = std::clamp(g[k], r.lower, r.upper);
  }
  return g;
}

// Element e's simulated part of the output (its gain included), each segment from rest.
Eigen::VectorXd element_part(const Eigen::MatrixXd& U, int input, const ElementModel& g,
                             double T_min, const SampleLayout& layout) {
  Eigen::VectorXd z(U.rows());
  const auto u = U.col(input);
  simulate_segments(discretise(g, T_min), {u.data(), static_cast<std::size_t>(u.size())},
                    {z.data(), static_cast<std::size_t>(z.size())}, layout.segments);
  return z;
}

struct AloneFit {
  ElementModel element;
  double sse = std::numeric_limits<double>::infinity();
};

// What an element's last screening found: the output error each other structure reached
// alone on its part of the output, while the element kept the structure `own`. A later round
// fits a structure again only when it could become a candidate on the part as it is now:
// no structure fits a part that moved by ‖Δ‖ (weighted) better than √SSE − ‖Δ‖ (the
// triangle inequality, the earlier fits taken as minima). After a change of another element
// of the row, a part moves little, and most fits of the round that ends the search are saved;
// an element any structure could still improve is screened again, each structure from the
// end it reached last time alone (one start, not structure_starts(): the part moved little,
// and the earlier screening's starts already chose the basin; on the 17 case-study runs of
// alatiqi4x4 the same models to the printed digits at 0.78 of the CPU time).
struct Screening {
  bool screened = false;
  Structure own = Structure::two_poles;
  Eigen::VectorXd part;  // the part the errors were measured on
  std::array<double, kStructures> sse{};
  std::array<ElementModel, kStructures> end{};  // per structure: its best end alone (own: the
                                                // element's value then)
  // Where a new screening of structure s starts from.
  std::vector<ElementModel> starts(Structure s, const ElementModel& now,
                                   const MisoBounds& bounds) const {
    const auto k = static_cast<std::size_t>(s);
    if (screened && (s == own || std::isfinite(sse[k]))) return {end[k]};
    return structure_starts(now, s, bounds);
  }
};

// Whether the exact discretisation takes every element of a start (a start it cannot take,
// poles ≪ T, would leave the fit nowhere to begin: not tried).
bool discretisable(const std::vector<ElementModel>& start, double T_min) {
  for (const ElementModel& g : start) {
    try {
      (void)discretise(g, T_min);
    } catch (const std::invalid_argument&) {
      return false;
    }
  }
  return true;
}

// Every start that the exact discretisation takes, polished alone; the best end.
AloneFit fit_alone(const Eigen::MatrixXd& U, const Eigen::VectorXd& part, int input,
                   const std::vector<ElementModel>& starts, double T_min, const MisoBounds& bounds,
                   const SampleLayout& layout) {
  AloneFit best;
  for (const ElementModel& s : starts) {
    if (!discretisable({s}, T_min)) continue;
    const MisoResult alone =
        fit_miso(U, part, {input}, {s}, T_min, bounds, kTrialAloneIterations, layout,
                 Eigen::MatrixXd(U.rows(), 0), LmOptions{}.cost_tolerance, MisoUncertainty::none);
    const double sse = weighted_sse(alone.y_hat, part, layout);
    if (sse < best.sse) best = {alone.elements.front().value, sse};
  }
  return best;
}

// Each element's share of its row: the norm of its simulated part over the sum of the
// elements' (weighted rows).
std::vector<double> part_shares(const Eigen::MatrixXd& U, const std::vector<int>& inputs,
                                const MisoResult& fit, double T_min, const SampleLayout& layout) {
  std::vector<double> share(inputs.size(), 0.0);
  double total = 0.0;
  for (std::size_t e = 0; e < inputs.size(); ++e) {
    share[e] = element_part(U, inputs[e], fit.elements[e].value, T_min, layout)
                   .cwiseProduct(layout.weight)
                   .norm();
    total += share[e];
  }
  for (double& s : share) s = total > 0.0 ? s / total : 0.0;
  return share;
}

// The row refitted from `start`; kept in `current` when it lowers the row's criterion
// (row_criterion: a restart in another structure pays for its parameters). A start the
// discretisation cannot take is not tried (alatiqi4x4 msSrdSimDir, seed 187, on the first
// 20 % of the run: a weak element restarted with its row's slowest lag made the whole
// identification throw). Nor is a start that could not lower the criterion even fitting
// exactly: its structures' criterion at zero error not below the row's (a row already at
// row_criterion's floor, noise-free, restarted in structures no smaller; on the noise-free
// twoweak4x4 prbsSimDir run these refits were 46 % of the identification's CPU time).
bool keep_if_better(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                    const std::vector<int>& inputs, const std::vector<ElementModel>& start,
                    double T_min, const MisoBounds& bounds, const SampleLayout& layout,
                    const Eigen::MatrixXd& trend, int max_iterations, MisoResult& current,
                    int& iterations, double margin = 0.0) {
  const Eigen::VectorXd y_scored = layout.scored_rows(y);
  const double energy = (y_scored.array() - y_scored.mean()).matrix().squaredNorm();
  const double now = row_criterion(weighted_sse(current.y_hat, y, layout), energy, layout.scored(),
                                   parameter_count(current.elements));
  if (!(row_criterion(0.0, energy, layout.scored(), parameter_count(start)) < now - margin))
    return false;
  if (!discretisable(start, T_min)) return false;
  MisoResult other = fit_miso(U, y, inputs, start, T_min, bounds, max_iterations, layout, trend);
  iterations += other.iterations;
  const double reached = row_criterion(weighted_sse(other.y_hat, y, layout), energy,
                                       layout.scored(), parameter_count(other.elements));
  if (!(reached < now - margin)) return false;
  current = std::move(other);
  return true;
}

// Two local optima the search above does not leave, each tried from the other side:
//  - An element the row's others can compensate for: a weak one (|K| < kWeakRatio·SE(K)) or a
//    small one (its simulated part below kSmallShare of the row's). alatiqi4x4 prbsSimDir,
//    seed 1, ended with (y2, u3) = +0.021 (true −0.05) at 87.10 %, the true model fitting
//    87.15 %; restarted with its gain of either sign and its row's slowest lag, the row reached
//    −0.050 at 87.17 %. Over 100 seeds of that design (tests/integration/host_calibration), the
//    row refitted from the true model still fitted better than the search's end by more than
//    ln N σ̂² in 12 seeds of row y2 and 22 of row y4 ((y4, u3), true K = −0.1 with lags 31.6
//    and 5, ended at T_p1 ≈ 60, its own slowest lag, or first order). So each such element is
//    restarted from 8 starts: either sign, its lags at the other elements' slowest lag and at
//    a quarter of it, in its own structure and (when the search chooses structures) in two
//    poles; a start is kept when it lowers the row's criterion. Those seeds fell to 3 and 0.
//  - A delay near a whole number of samples sits at a kink of the output error (the ZOH
//    response's taps change form there), with a local optimum on either side; which one a fit
//    reaches depends on its path, so rounding decided it (woodberry2x2 prbsSeqDir: T_d =
//    2.994 in-process, 3.010 through the gateway, fits 90.1405 and 90.1408 %). Both sides.
// `keep_structures`: a forced structure is restarted in itself only.
MisoResult leave_local_optima(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                              const std::vector<int>& inputs, MisoResult current, double T_min,
                              const MisoBounds& bounds, const SampleLayout& layout,
                              const Eigen::MatrixXd& trend, int max_iterations,
                              bool keep_structures) {
  int iterations = current.iterations;
  const auto try_from = [&](const std::vector<ElementModel>& start) {
    keep_if_better(U, y, inputs, start, T_min, bounds, layout, trend, max_iterations, current,
                   iterations);
  };
  const std::vector<double> share = part_shares(U, inputs, current, T_min, layout);
  for (std::size_t e = 0; e < inputs.size(); ++e) {
    const ElementEstimate est = current.elements[e];  // a copy: the restarts replace `current`
    const bool weak = std::abs(est.value.gain) < kWeakRatio * est.std_error.gain;
    const bool small = inputs.size() > 1 && share[e] < kSmallShare;
    if (!weak && !small) continue;
    // The row's other elements' slowest lag: the time scale of the process the element
    // shares (its own lags are what the data know least).
    double slowest = 0.0;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const ElementModel& other = current.elements[k].value;
      if (k != e) slowest = std::max({slowest, other.tau1_min, other.tau2_min});
    }
    if (!(slowest > 0.0)) slowest = std::max(est.value.tau1_min, est.value.tau2_min);
    const Structure own = est.value.structure;
    std::vector<Structure> structures{own};
    if (!keep_structures && own != Structure::two_poles) structures.push_back(Structure::two_poles);
    for (const Structure s : structures) {
      for (const double scale : kRestartScales) {
        for (const double sign : {-1.0, 1.0}) {
          // From the row as it is now (an earlier start may have moved it).
          std::vector<ElementModel> start = values_of(current);
          ElementModel g = with_structure(start[e], s);
          g.gain = sign * std::abs(start[e].gain);
          if (is_free(g.structure, kTp1)) g.tau1_min = scale * slowest;
          // not equal: T_p1 = T_p2 is a saddle of the symmetric fit
          if (is_free(g.structure, kTp2)) g.tau2_min = scale * slowest / 2.0;
          start[e] = clamped(g, bounds);
          try_from(start);
        }
      }
    }
  }
  for (std::size_t e = 0; e < inputs.size(); ++e) {
    const double td = current.elements[e].value.delay_min;
    const double whole = std::round(td / T_min);
    if (whole < 1.0 || std::abs(td - whole * T_min) > kDelayKink * T_min) continue;
    std::vector<ElementModel> start = values_of(current);
    start[e].delay_min =
        td < whole * T_min ? (whole + kDelayKink) * T_min : (whole - kDelayKink) * T_min;
    start[e] = clamped(start[e], bounds);
    try_from(start);
  }
  current.iterations = iterations;
  return current;
}

// The residual's Bartlett long-run variance over `lags` (at most a quarter of its rows) over
// its variance: about how many of its rows count as one independent row. 1 for a white
// residual; a linear model of a nonlinear plant leaves a slowly wandering one.
double colour_ratio(const Eigen::VectorXd& residual, Eigen::Index lags) {
  const Eigen::VectorXd x = residual.array() - residual.mean();
  const double variance = x.squaredNorm();
  if (!std::isfinite(variance) || !(variance > 0.0)) return 1.0;
  const Eigen::Index L = std::min<Eigen::Index>(lags, x.size() / 4);
  return std::max(1.0, long_run_covariance(x, L)(0, 0) / variance);
}

// The search above screens each element on its part of the output with the others held, and
// restarts only weak and small ones; under a directional design's correlated inputs a large
// element's dynamics can end on another element, where no single change moves them back.
// alatiqi4x4 with (y4, u2)'s delay 0.52 instead of 0.02, prbsSimDir, seed 8: (y4, u2) =
// 14 (10s+1) e^{−0.52s} / ((45s+1)(17.4s²+3s+1)) ended first order, its oscillating pair on
// the tiny (y4, u3), the row at 85.4 % with a residual far from white (Q = 1.2·10⁴, limit 44)
// and dependent on u2 (S = 206, limit 46); over 60 seeds 14 rows ended worse than the refit
// from the truth. That residual is the evidence: when the row's residual is not white (Ljung's
// tests at 1 %, residuals.hpp), the elements whose input it depends on — or, when it depends
// on none, every element — are restarted, the two most dependent first, with the row from
// every structure's starts, once as the row is and once with the row's other elements
// released to two poles (a pair or a zero they hold may be theirs); a start is kept when it
// lowers the row's criterion. A row whose residual is white, or at rounding (noise-free),
// costs one residual test. On the 17 case-study runs of alatiqi4x4 four rows are restarted,
// and each ends at a lower criterion (seven elements in their true structures; msSrdSimDir's
// row y4 97.48 → 98.43 %), at 1.6 times the CPU time of the 17 identifications.
// Returns whether a start was kept. Not for forced structures (it tries them all).
bool restart_misplaced_dynamics(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                                const std::vector<int>& inputs, MisoResult& current, double T_min,
                                const MisoBounds& bounds, const SampleLayout& layout,
                                const Eigen::MatrixXd& trend, int max_iterations) {
  const Eigen::VectorXd y_scored = layout.scored_rows(y);
  const Eigen::VectorXd residual = y_scored - layout.scored_rows(current.y_hat);
  const double energy = (y_scored.array() - y_scored.mean()).matrix().squaredNorm();
  if (!residual.allFinite() || residual.size() <= 2 * kResidualTestLags ||
      residual.squaredNorm() <= 100.0 * kSseFloor * energy) {
    return false;
  }
  Eigen::MatrixXd U_scored(residual.size(), static_cast<Eigen::Index>(inputs.size()));
  for (std::size_t e = 0; e < inputs.size(); ++e)
    U_scored.col(static_cast<Eigen::Index>(e)) = layout.scored_rows(U.col(inputs[e]));
  const ResidualTests tests = residual_tests(residual, U_scored, kResidualTestLags);
  if (tests.white()) return false;
  // The elements whose input the residual depends on, most first; when it depends on none
  // (a coloured residual under a multisine's few lines: msSrdSimDir's row y4 ended at 97.48 %
  // with Q = 1.2·10⁴ where 98.43 % was there), every element, in the same order.
  std::vector<std::size_t> suspects(inputs.size());
  for (std::size_t e = 0; e < inputs.size(); ++e) suspects[e] = e;
  std::sort(suspects.begin(), suspects.end(), [&](std::size_t a, std::size_t b) {
    return tests.independence(static_cast<Eigen::Index>(a)) >
           tests.independence(static_cast<Eigen::Index>(b));
  });
  const auto independent = std::find_if(suspects.begin(), suspects.end(), [&](std::size_t e) {
    return tests.independent_of(static_cast<Eigen::Index>(e));
  });
  const bool none_dependent = independent == suspects.begin();
  if (!none_dependent) suspects.erase(independent, suspects.end());
  // A residual that depends on no input is evidence of a misplaced element only as far as
  // its colour allows: the criterion counts every row as independent, and a residual of
  // long-run variance ratio r carries about one independent sample in r, so a restart from it
  // is kept when it lowers the criterion by more than kEvidence · r. (Window: the slowest time
  // constant the fit allows, the settling time β·τ_H in the adaptive test.)
  double margin = 0.0;
  if (none_dependent) {
    const auto window = static_cast<Eigen::Index>(std::ceil(bounds.max_time_constant_min / T_min));
    margin = kEvidence * colour_ratio(residual, std::max<Eigen::Index>(window, 1));
  }
  if (suspects.size() > kMisplacedRestarts) suspects.resize(kMisplacedRestarts);

  bool kept = false;
  int iterations = current.iterations;
  for (const std::size_t e : suspects) {
    const std::vector<ElementModel> now = values_of(current);
    // The row's other elements in two poles: lags their slowest time scale and the next.
    std::vector<ElementModel> released = now;
    bool any_released = false;
    for (std::size_t k = 0; k < now.size(); ++k) {
      const Structure s = now[k].structure;
      if (k == e || s == Structure::first_order || s == Structure::two_poles ||
          s == Structure::integrator) {
        continue;
      }
      std::vector<double> lags;
      for (const int q : {kTp1, kTp2, kNatural})
        if (is_free(s, q) && now[k][q] > 0.0) lags.push_back(now[k][q]);
      std::sort(lags.rbegin(), lags.rend());
      ElementModel g = with_structure(now[k], Structure::two_poles);
      g.tau1_min = lags.empty() ? 0.0 : lags[0];
      g.tau2_min = lags.size() > 1 ? lags[1] : g.tau1_min / 4.0;
      released[k] = clamped(g, bounds);
      any_released = true;
    }
    for (int q = 0; q < kStructures; ++q) {
      for (const ElementModel& g : structure_starts(now[e], static_cast<Structure>(q), bounds)) {
        for (const bool release : {false, true}) {
          if (release && !any_released) continue;
          std::vector<ElementModel> start = release ? released : now;
          start[e] = g;
          kept = keep_if_better(U, y, inputs, start, T_min, bounds, layout, trend, max_iterations,
                                current, iterations, margin) ||
                 kept;
        }
      }
    }
  }
  current.iterations = iterations;
  return kept;
}

}  // namespace

double row_criterion(double sse, double y_energy, Eigen::Index scored_rows,
                     Eigen::Index parameters) {
  const auto M = static_cast<double>(std::max<Eigen::Index>(scored_rows, 1));
  const double floor = kSseFloor * y_energy;
  return M * std::log(std::max({sse, floor, std::numeric_limits<double>::min()}) / M) +
         static_cast<double>(parameters) * std::log(M);
}

std::vector<ElementModel> structure_starts(const ElementModel& g, Structure s,
                                           const MisoBounds& bounds) {
  // g's time scales: its lags (T_p1, T_p2, T_n where it has them), slowest first.
  std::vector<double> lags;
  for (const int k : {kTp1, kTp2, kNatural}) {
    if (is_free(g.structure, k) && g[k] > 0.0) lags.push_back(g[k]);
  }
  std::sort(lags.rbegin(), lags.rend());
  const double slow = lags.empty() ? 0.0 : lags[0];
  const double fast = lags.size() > 1 ? lags[1] : slow / 4.0;
  ElementModel base = with_structure(ElementModel{}, s);
  base.gain = g.gain;
  base.delay_min = g.delay_min;
  std::vector<ElementModel> out;
  const auto add = [&](ElementModel e) { out.push_back(clamped(e, bounds)); };
  switch (s) {
    case Structure::first_order: {
      ElementModel a = base;
      a.tau1_min = slow + fast;
      add(a);
      ElementModel b = base;
      b.delay_min = g.delay_min + fast;
      b.tau1_min = slow;
      add(b);
      break;
    }
    case Structure::two_poles: {
      ElementModel a = base;
      a.tau1_min = slow;
      a.tau2_min = fast;
      add(a);
      break;
    }
    case Structure::two_poles_zero:
      for (const double tz : {0.0, 0.5 * slow, -fast}) {
        ElementModel a = base;
        a.tau1_min = slow;
        a.tau2_min = fast;
        a.zero_min = tz;
        add(a);
      }
      break;
    case Structure::integrator: {
      ElementModel a = base;
      a.gain = slow > 0.0 ? g.gain / slow : g.gain;
      a.tau1_min = lags.size() > 1 ? fast : 0.0;
      add(a);
      break;
    }
    case Structure::underdamped:
      for (const double zeta : {0.3, 0.7}) {
        ElementModel a = base;
        a.natural_min = std::sqrt(slow * fast);
        a.damping = zeta;
        add(a);
      }
      break;
    case Structure::underdamped_lag_zero:
      for (const double zeta : {0.3, 0.7}) {
        for (const double tz : {0.0, 0.5 * slow}) {
          ElementModel a = base;
          a.tau1_min = slow;
          a.natural_min = fast;
          a.damping = zeta;
          a.zero_min = tz;
          add(a);
        }
      }
      break;
  }
  return out;
}

namespace {

// One output's structure search (choose_structures): the data, bounds and criterion every
// step shares, and the steps — the forced structures, one round of screening, the trial of
// its candidates, the rounds from a start.
class StructureSearcher {
 public:
  StructureSearcher(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                    const std::vector<int>& inputs, double T_min, const MisoBounds& bounds,
                    const SampleLayout& layout, const Eigen::MatrixXd& trend,
                    const StructureSearch& search)
      : U_(U),
        y_(y),
        inputs_(inputs),
        T_min_(T_min),
        bounds_(bounds),
        layout_(layout),
        trend_(trend),
        search_(search) {}

  // The structure forced on element e, if any.
  std::optional<Structure> forced_on(std::size_t e) const {
    if (!search_.per_element.empty()) return search_.per_element.at(e);
    return search_.forced;
  }
  bool all_forced() const { return search_.forced.has_value() || !search_.per_element.empty(); }

  MisoResult leave_optima(MisoResult fit, bool keep_structures) const {
    return leave_local_optima(U_, y_, inputs_, std::move(fit), T_min_, bounds_, layout_, trend_,
                              search_.max_iterations, keep_structures);
  }

  // Every element fitted alone in its forced structure from the two-pole fit, then the row.
  MisoResult forced_fit(const MisoResult& two_poles) const {
    std::vector<ElementModel> start;
    for (std::size_t e = 0; e < inputs_.size(); ++e) {
      const Structure s = *forced_on(e);
      const ElementModel& g = two_poles.elements[e].value;
      start.push_back(s == Structure::two_poles
                          ? g
                          : fit_alone(U_, part_of(two_poles, e), inputs_[e],
                                      structure_starts(g, s, bounds_), T_min_, bounds_, layout_)
                                .element);
    }
    MisoResult forced = refit(start);
    forced.iterations += two_poles.iterations;
    return leave_optima(std::move(forced), true);
  }

  // Rounds of structure changes from `current` (each element screened on its part of the
  // output, the candidates refitted with the row), then its local optima left.
  MisoResult search_from(MisoResult current) {
    energy_and_rows();
    Progress p{std::move(current), 0.0, 0};
    p.criterion = criterion(p.fit);
    p.iterations = p.fit.iterations;  // of every fit made, for MisoResult::iterations
    std::vector<Screening> screened(inputs_.size());
    for (int round = 0; round < kRounds; ++round) {
      std::vector<Candidate> candidates;
      for (std::size_t e = 0; e < inputs_.size(); ++e) {
        if (auto c = screen(p.fit, e, screened[e])) candidates.push_back(std::move(*c));
      }
      if (candidates.empty() || !try_candidates(p, std::move(candidates))) break;
    }
    p.fit.iterations = p.iterations;
    return leave_optima(std::move(p.fit), false);
  }

 private:
  // An element's best other structure on its own part of the output, and by how much it
  // lowers that part's criterion.
  struct Candidate {
    std::size_t element;
    ElementModel model;
    double gain;
  };
  // The fit the rounds have reached, its criterion, and the iterations of every fit made.
  struct Progress {
    MisoResult fit;
    double criterion;
    int iterations;
  };

  void energy_and_rows() {
    const Eigen::VectorXd y_scored = layout_.scored_rows(y_);
    energy_ = (y_scored.array() - y_scored.mean()).matrix().squaredNorm();
    M_ = layout_.scored();
  }
  double criterion(const MisoResult& fit) const {
    return row_criterion(weighted_sse(fit.y_hat, y_, layout_), energy_, M_,
                         parameter_count(fit.elements));
  }
  double alone_criterion(double sse, Structure s) const {
    return row_criterion(sse, energy_, M_, static_cast<Eigen::Index>(free_parameters(s).size()));
  }
  MisoResult refit(const std::vector<ElementModel>& start) const {
    return fit_miso(U_, y_, inputs_, start, T_min_, bounds_, search_.max_iterations, layout_,
                    trend_);
  }
  // Element e's part of the output under `fit`: y minus the other elements and the trend.
  Eigen::VectorXd part_of(const MisoResult& fit, std::size_t e) const {
    return y_ - fit.y_hat + element_part(U_, inputs_[e], fit.elements[e].value, T_min_, layout_);
  }

  // Element e screened on its part of `current` (skipped when no structure could gain on
  // what its part moved since `last`, see Screening); a candidate when another structure
  // lowers that part's criterion by more than kEvidence.
  std::optional<Candidate> screen(const MisoResult& current, std::size_t e, Screening& last) const {
    const Eigen::VectorXd part = part_of(current, e);
    const ElementModel& now = current.elements[e].value;
    const double own = alone_criterion(weighted_sse(current.y_hat, y_, layout_), now.structure);
    if (last.screened && last.own == now.structure) {
      // The lowest output error each structure can reach on the moved part (see Screening).
      const double moved = (part - last.part).cwiseProduct(layout_.weight).norm();
      bool could = false;
      for (int k = 0; k < kStructures && !could; ++k) {
        const double reach =
            std::max(std::sqrt(last.sse[static_cast<std::size_t>(k)]) - moved, 0.0);
        could = static_cast<Structure>(k) != now.structure &&
                alone_criterion(reach * reach, static_cast<Structure>(k)) < own - kEvidence;
      }
      if (!could) return std::nullopt;
    }
    const Screening before = last;
    last = {true, now.structure, part, {}, {}};
    last.sse.fill(std::numeric_limits<double>::infinity());
    last.end[static_cast<std::size_t>(now.structure)] = now;
    double best = own;
    std::optional<ElementModel> better;
    for (int k = 0; k < kStructures; ++k) {
      const auto s = static_cast<Structure>(k);
      if (s == now.structure) continue;
      const AloneFit alone =
          fit_alone(U_, part, inputs_[e], before.starts(s, now, bounds_), T_min_, bounds_, layout_);
      last.sse[static_cast<std::size_t>(k)] = alone.sse;
      last.end[static_cast<std::size_t>(k)] = alone.element;
      const double c = alone_criterion(alone.sse, s);
      if (c < best) {
        best = c;
        better = alone.element;
      }
    }
    if (better && best < own - kEvidence) return Candidate{e, *better, own - best};
    return std::nullopt;
  }

  // The largest change alone and every change at once (one joint fit each), the better kept
  // when it lowers the row's criterion by more than kEvidence; else the other changes one at
  // a time. Whether `p` changed.
  bool try_candidates(Progress& p, std::vector<Candidate> candidates) const {
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.gain > b.gain; });
    const auto trial_of = [&](std::size_t first, std::size_t last) {
      std::vector<ElementModel> start = values_of(p.fit);
      for (std::size_t k = first; k < last; ++k) start[candidates[k].element] = candidates[k].model;
      MisoResult trial = refit(start);
      p.iterations += trial.iterations;
      return trial;
    };
    const auto accept = [&](MisoResult& trial, double c) {
      if (!(c < p.criterion - kEvidence)) return false;
      p.fit = std::move(trial);
      p.criterion = c;
      return true;
    };
    MisoResult best_trial = trial_of(0, 1);
    double best_criterion = criterion(best_trial);
    if (candidates.size() > 1) {
      MisoResult all = trial_of(0, candidates.size());
      const double c = criterion(all);
      if (c < best_criterion) {
        std::swap(best_trial, all);
        best_criterion = c;
      }
    }
    bool changed = accept(best_trial, best_criterion);
    for (std::size_t k = 1; !changed && k < candidates.size(); ++k) {
      MisoResult trial = trial_of(k, k + 1);
      changed = accept(trial, criterion(trial));
    }
    return changed;
  }

  const Eigen::MatrixXd& U_;
  const Eigen::VectorXd& y_;
  const std::vector<int>& inputs_;
  double T_min_;
  const MisoBounds& bounds_;
  const SampleLayout& layout_;
  const Eigen::MatrixXd& trend_;
  const StructureSearch& search_;
  double energy_ = 0.0;  // of the scored output about its mean (row_criterion's floor)
  Eigen::Index M_ = 0;   // scored rows
};

}  // namespace

MisoResult choose_structures(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                             const std::vector<int>& inputs, MisoResult two_poles, double T_min,
                             const MisoBounds& bounds, const SampleLayout& layout,
                             const Eigen::MatrixXd& trend, const StructureSearch& search) {
  StructureSearcher searcher(U, y, inputs, T_min, bounds, layout, trend, search);
  bool all_two_poles = searcher.all_forced();
  for (std::size_t e = 0; e < inputs.size(); ++e)
    all_two_poles = all_two_poles && searcher.forced_on(e) == Structure::two_poles;
  if (all_two_poles) return searcher.leave_optima(std::move(two_poles), true);
  if (searcher.all_forced()) return searcher.forced_fit(two_poles);
  MisoResult current = searcher.search_from(std::move(two_poles));
  if (restart_misplaced_dynamics(U, y, inputs, current, T_min, bounds, layout, trend,
                                 search.max_iterations)) {
    current = searcher.search_from(std::move(current));
  }
  return current;
}

MisoResult continue_structures(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                               const std::vector<int>& inputs, MisoResult fitted, double T_min,
                               const MisoBounds& bounds, const SampleLayout& layout,
                               const Eigen::MatrixXd& trend, const StructureSearch& search) {
  StructureSearcher searcher(U, y, inputs, T_min, bounds, layout, trend, search);
  if (searcher.all_forced()) return searcher.leave_optima(std::move(fitted), true);
  MisoResult current = searcher.search_from(std::move(fitted));
  if (restart_misplaced_dynamics(U, y, inputs, current, T_min, bounds, layout, trend,
                                 search.max_iterations)) {
    current = searcher.search_from(std::move(current));
  }
  return current;
}

}  // namespace excite::host
