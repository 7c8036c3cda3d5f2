// SPDX-License-Identifier: MIT
#include "host/identify/identify.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"
#include "host/identify/arx_start.hpp"
#include "host/identify/gain_profile.hpp"
#include "host/identify/grade.hpp"
#include "host/identify/input_screen.hpp"
#include "host/identify/inputs_together.hpp"
#include "host/identify/miso_fit.hpp"
#include "host/identify/own_part_start.hpp"
#include "host/identify/response_bank.hpp"
#include "host/identify/structure_search.hpp"
#include "host/identify/validate.hpp"
#include "host/process/parallel.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_finite(const Eigen::MatrixXd& M, const char* name) {
  for (Eigen::Index c = 0; c < M.cols(); ++c) {
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      if (!std::isfinite(M(r, c))) {
        throw std::invalid_argument(std::string("identify: ") + name + " sample " +
                                    std::to_string(r) + " (row), channel " + std::to_string(c + 1) +
                                    " is " + config::format_number(M(r, c)) +
                                    "; data must be finite");
      }
    }
  }
}

void check_arguments(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T_min,
                     const SampleLayout& layout, const IdentifyOptions& o) {
  if (!std::isfinite(T_min) || T_min <= 0.0) {
    throw std::invalid_argument("identify: sample time T_min = " + config::format_number(T_min) +
                                ", expected a finite number > 0 (minutes)");
  }
  if (!std::isfinite(o.max_delay_min) || o.max_delay_min < 0.0) {
    throw std::invalid_argument(
        "identify: max_delay_min = " + config::format_number(o.max_delay_min) +
        ", expected a finite number ≥ 0 (minutes)");
  }
  if (!std::isfinite(o.max_time_constant_min) || o.max_time_constant_min < 0.0) {
    throw std::invalid_argument(
        "identify: max_time_constant_min = " + config::format_number(o.max_time_constant_min) +
        ", expected a finite number ≥ 0 (0: the experiment length)");
  }
  if (o.max_iterations < 1) {
    throw std::invalid_argument("identify: max_iterations = " + std::to_string(o.max_iterations) +
                                ", expected ≥ 1");
  }
  if (o.threads < 1) {
    throw std::invalid_argument("identify: threads = " + std::to_string(o.threads) +
                                ", expected ≥ 1");
  }
  if (U.cols() == 0 || Y.cols() == 0) {
    throw std::invalid_argument("identify: U has " + std::to_string(U.cols()) + " inputs and Y " +
                                std::to_string(Y.cols()) +
                                " outputs, expected at least one of each");
  }
  if (U.rows() != Y.rows()) {
    throw std::invalid_argument("identify: U has " + std::to_string(U.rows()) +
                                " samples (rows) but Y has " + std::to_string(Y.rows()) +
                                ", expected one row per sample in both");
  }
  if (layout.rows() != U.rows()) {
    throw std::invalid_argument("identify: the sample layout has " + std::to_string(layout.rows()) +
                                " rows but the data " + std::to_string(U.rows()) +
                                ", expected one weight per row");
  }
  if (!o.structures.empty() &&
      o.structures.size() != static_cast<std::size_t>(U.cols() * Y.cols())) {
    throw std::invalid_argument("identify: structures has " + std::to_string(o.structures.size()) +
                                " entries, expected one per element, " +
                                std::to_string(Y.cols() * U.cols()) + " (outputs × inputs)");
  }
  if (!o.structures.empty() && o.structure) {
    throw std::invalid_argument(std::string("identify: structure = ") + to_string(*o.structure) +
                                " and per-element structures both given, expected one of them");
  }
  layout.check();
  const Eigen::Index need = minimum_samples(static_cast<int>(U.cols()), T_min, o);
  if (layout.scored() < need) {
    throw std::invalid_argument(
        "identify: " + std::to_string(layout.scored()) + " samples are too few for " +
        std::to_string(U.cols()) + " inputs with delays up to " +
        config::format_number(o.max_delay_min) + " min at T = " + config::format_number(T_min) +
        " min, expected at least " + std::to_string(need) +
        " (⌈max_delay/T⌉ + 10 per parameter, 4 parameters per input)");
  }
  check_finite(U, "U");
  check_finite(Y, "Y");
}

// Multi-start: the second start is polished too when its output error is within this
// factor of the better start's (the two are then not clearly ranked).
constexpr double kAmbiguousStart = 4.0;
// Iterations for one element fitted alone to its part of the output (a start only).
constexpr int kStartAloneIterations = 30;
// A cold end whose cost is below this share of the output's (in squares; row_criterion's
// floor, structure_search.cpp) fits noise-free data in the model class: the own-part starts
// cannot lead anywhere better.
constexpr double kNoiseFree = 1e-12;

// ‖y − ŷ‖² over the scored rows of the start elements (one per input of `inputs`).
double start_cost(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                  const std::vector<int>& inputs, const std::vector<ElementModel>& start,
                  double T_min, const SampleLayout& layout, const Eigen::MatrixXd& trend) {
  Eigen::VectorXd r = y;
  Eigen::VectorXd z(y.size());
  for (std::size_t e = 0; e < inputs.size(); ++e) {
    ElementModel unit = start[e];
    unit.gain = 1.0;
    const auto u = U.col(inputs[e]);
    simulate_segments(discretise(unit, T_min), {u.data(), static_cast<std::size_t>(u.size())},
                      {z.data(), static_cast<std::size_t>(z.size())}, layout.segments);
    r -= start[e].gain * z;
  }
  r = r.cwiseProduct(layout.weight);
  if (trend.cols() > 0) r -= trend * (trend.transpose() * r);
  return r.squaredNorm();
}

// Row j's warm start (IdentifyOptions::start): its usable elements' values, each clamped into
// the bounds of this fit; none when the start is of another size, an element of the row is
// not estimated in it or is not in the structure forced on it.
std::optional<std::vector<ElementModel>> warm_start_of(const IdentifyOptions& o, int j, int n,
                                                       int p, const std::vector<int>& usable,
                                                       const MisoBounds& bounds) {
  if (!o.start || o.start->inputs != n || o.start->outputs != p || usable.empty())
    return std::nullopt;
  std::vector<ElementModel> start;
  for (const int i : usable) {
    const ElementEstimate& e = o.start->element(j, i);
    if (!e.estimated()) return std::nullopt;
    const Structure forced = !o.structures.empty()
                                 ? o.structures[static_cast<std::size_t>(j * n + i)]
                                 : o.structure.value_or(e.value.structure);
    if (forced != e.value.structure) return std::nullopt;
    ElementModel g = e.value;
    for (const int k : free_parameters(g.structure)) {
      if (!std::isfinite(g[k])) return std::nullopt;
      const ParameterRange r = parameter_range(k, bounds);
      g[k] = std::clamp(g[k], r.lower, r.upper);
    }
    start.push_back(g);
  }
  return start;
}

void mark_row(IdentifiedModel& model, int out, ElementStatus status, const std::string& why) {
  for (int i = 0; i < model.inputs; ++i) {
    ElementEstimate& e = model.element(out, i);
    e.value = ElementModel{kNaN, kNaN, kNaN, kNaN};
    e.std_error = e.value;
    e.status = status;
    e.reason = why;
  }
}

}  // namespace

Eigen::Index minimum_samples(int inputs, double T_min, const IdentifyOptions& options) {
  const double delay_samples = std::ceil(options.max_delay_min / T_min);
  return static_cast<Eigen::Index>(delay_samples) + 10 * 4 * static_cast<Eigen::Index>(inputs);
}

IdentificationResult identify(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T_min,
                              const IdentifyOptions& options) {
  return identify(U, Y, T_min, SampleLayout::whole(U.rows()), options);
}

namespace {

// Transient time constants in samples (IdentifyOptions::estimate_initial_state): T_p max / 2^k
// for k = 0…5, those of at least one sample.
std::vector<double> transient_samples(const IdentifyOptions& o, double tp_max, double T_min) {
  std::vector<double> transients;
  for (int k = 0; o.estimate_initial_state && k <= 5; ++k) {
    const double tau = tp_max / T_min / std::pow(2.0, k);
    if (tau >= 1.0) transients.push_back(tau);
  }
  return transients;
}

// Inputs whose gains' split rests on the elements' dynamics alone (issue 43): the usable
// inputs (as positions in `usable`) whose own part is below kCannotSplit, which two more
// starts give one shared grid element (choose_shared) or, for a pair, the best pair of grid
// elements (choose_pair).
std::vector<Eigen::Index> inputs_moving_together(const Eigen::MatrixXd& U_scored,
                                                 const std::vector<int>& usable) {
  std::vector<Eigen::Index> together;
  if (usable.size() <= 1) return together;
  Eigen::MatrixXd moved(U_scored.rows(), static_cast<Eigen::Index>(usable.size()));
  for (std::size_t e = 0; e < usable.size(); ++e)
    moved.col(static_cast<Eigen::Index>(e)) = U_scored.col(usable[e]);
  const InputSeparation separation = input_separation(moved);
  for (Eigen::Index e = 0; e < separation.independent.size(); ++e) {
    if (separation.independent(e) < kCannotSplit) together.push_back(e);
  }
  return together;
}

// What every output's fit shares: the data and options, the screen of the inputs, each row's
// warm start, the cold starts' response bank and ARX basis (built only when a row needs them),
// the trend basis and the inputs that move together. Built once, read by every row's thread.
struct Rows {
  Rows(const Eigen::MatrixXd& U_, const Eigen::MatrixXd& Y_, double T, const SampleLayout& l,
       const IdentifyOptions& o)
      : U(U_),
        Y(Y_),
        T_min(T),
        layout(l),
        options(o),
        n(static_cast<int>(U_.cols())),
        p(static_cast<int>(Y_.cols())),
        tp_max(o.max_time_constant_min > 0.0 ? o.max_time_constant_min
                                             : static_cast<double>(U_.rows()) * T),
        screen(screen_inputs(U_)),
        bounds{o.max_delay_min, tp_max, natural_period_floor(T)},
        warm(static_cast<std::size_t>(p)),
        trend(trend_basis(l, o.trend, transient_samples(o, tp_max, T))),
        U_scored(l.scored(), n) {
    bool any_cold = false;
    for (int j = 0; j < p; ++j) {
      warm[static_cast<std::size_t>(j)] = warm_start_of(o, j, n, p, screen.usable, bounds);
      any_cold = any_cold || !warm[static_cast<std::size_t>(j)];
    }
    if (any_cold) {
      bank.emplace(U, screen.usable, T_min, GridSpec{o.max_delay_min, tp_max}, layout);
      arx.emplace(U, screen.usable, T_min, o.max_delay_min, layout);
    }
    for (int i = 0; i < n; ++i) U_scored.col(i) = layout.scored_rows(U.col(i));
    together = inputs_moving_together(U_scored, screen.usable);
    if (any_cold && together.size() == 2) {
      own_part.emplace(U, screen.usable, static_cast<std::size_t>(together[0]),
                       static_cast<std::size_t>(together[1]), T_min, o.max_delay_min, layout);
    }
  }

  const Eigen::MatrixXd& U;
  const Eigen::MatrixXd& Y;
  const double T_min;
  const SampleLayout& layout;
  const IdentifyOptions& options;
  const int n;
  const int p;
  const double tp_max;
  const InputScreen screen;
  const MisoBounds bounds;
  std::vector<std::optional<std::vector<ElementModel>>> warm;
  std::optional<ResponseBank> bank;
  std::optional<ArxBasis> arx;
  const Eigen::MatrixXd trend;
  Eigen::MatrixXd U_scored;  // the inputs on the scored rows
  std::vector<Eigen::Index> together;
  std::optional<OwnPartStarts> own_part;  // for a pair that moves together, on a cold row
};

// Each usable element fitted alone to its own part of the output, as the row's ARX model
// splits it (a start: few iterations); none when the ARX model cannot split the output.
std::optional<std::vector<ElementModel>> arx_start(const Rows& rows,
                                                   const Eigen::VectorXd& y_start) {
  const auto Z = rows.arx->contributions(y_start);
  if (!Z) return std::nullopt;
  std::vector<ElementModel> start;
  for (std::size_t e = 0; e < rows.screen.usable.size(); ++e) {
    const auto col = static_cast<Eigen::Index>(e);
    const Eigen::VectorXd z = Z->col(col);
    double gain = 0.0;
    ElementModel g =
        rows.bank->grid()[static_cast<std::size_t>(rows.bank->choose_one(col, z, gain))];
    g.gain = gain;
    const MisoResult alone =
        fit_miso(rows.U, z, {rows.screen.usable[e]}, {g}, rows.T_min, rows.bounds,
                 kStartAloneIterations, rows.layout, Eigen::MatrixXd(y_start.size(), 0),
                 LmOptions{}.cost_tolerance, MisoUncertainty::none);
    start.push_back(alone.elements.front().value);
  }
  return start;
}

// The starts of a cold row: the row's ARX model (sees all elements at once; exact on data the
// structure fits), the grid basin search and, for inputs that move together, the shared and
// pair starts. `together` is where the starts for inputs that move together begin.
struct ColdStarts {
  std::vector<std::vector<ElementModel>> starts;
  std::size_t together = 0;
};

ColdStarts cold_starts(const Rows& rows, const Eigen::VectorXd& y_start) {
  const ResponseBank& bank = *rows.bank;
  ColdStarts c;
  if (auto arx = arx_start(rows, y_start)) c.starts.push_back(std::move(*arx));
  c.starts.push_back(bank.elements(bank.choose(y_start)));
  c.together = c.starts.size();
  if (rows.together.size() > 1) {
    c.starts.push_back(bank.elements(bank.choose_shared(y_start, rows.together)));
  }
  if (rows.together.size() == 2) {
    c.starts.push_back(
        bank.elements(bank.choose_pair(y_start, rows.together[0], rows.together[1])));
  }
  return c;
}

// A cold row (multi-start, cold_starts()). The start of least output error is polished; so is
// each other start within kAmbiguousStart of it, and always the starts for inputs that move
// together (their start costs say little about where the fits from them end). For a pair,
// unless the best end fits noise-free data (kNoiseFree: no start can do better, and on
// twoweak4x4's noise-free prbsSimDir run, whose pair is below kCannotSplit, they quadrupled
// its time), so are the starts from each one's own part (own_part_start.hpp), from the pair
// start, and then the best end with the pair's dynamics exchanged (OwnPartStarts::exchanged).
// The best end is kept and the structures chosen from it (structure_search.hpp). For a pair,
// every end is in `optima` (cover_other_optima()).
MisoResult fit_cold(const Rows& rows, const Eigen::VectorXd& y, const Eigen::VectorXd& y_start,
                    const StructureSearch& search, std::vector<RowOptimum>& optima) {
  const std::vector<int>& usable = rows.screen.usable;
  const ColdStarts c = cold_starts(rows, y_start);
  std::vector<double> cost;
  for (const auto& start : c.starts)
    cost.push_back(start_cost(rows.U, y, usable, start, rows.T_min, rows.layout, rows.trend));
  const auto first =
      static_cast<std::size_t>(std::min_element(cost.begin(), cost.end()) - cost.begin());
  const auto sse = [&](const MisoResult& m) {
    return (m.y_hat - y).cwiseProduct(rows.layout.weight).squaredNorm();
  };
  std::optional<MisoResult> miso;
  const auto fit_from = [&](const std::vector<ElementModel>& start) {
    MisoResult other = fit_miso(rows.U, y, usable, start, rows.T_min, rows.bounds,
                                rows.options.max_iterations, rows.layout, rows.trend);
    if (rows.own_part) optima.push_back({gains_of(other), sse(other), gain_errors_of(other)});
    if (!miso) {
      miso = std::move(other);
      return;
    }
    if (sse(other) < sse(*miso)) std::swap(*miso, other);
    miso->iterations += other.iterations;
  };
  fit_from(c.starts[first]);
  for (std::size_t s = 0; s < c.starts.size(); ++s) {
    if (s == first || (s < c.together && !(cost[s] <= kAmbiguousStart * cost[first]))) continue;
    fit_from(c.starts[s]);
  }
  // (own_part exists for a pair only, whose pair start cold_starts() put last)
  if (rows.own_part &&
      !(sse(*miso) <= kNoiseFree * y.cwiseProduct(rows.layout.weight).squaredNorm())) {
    const RowProblem row_start{rows.U,      y_start,     usable,
                               rows.T_min,  rows.bounds, rows.options.max_iterations,
                               rows.layout, rows.trend};
    for (const auto& start : rows.own_part->starts(row_start, *rows.bank, c.starts.back()))
      fit_from(start);
    fit_from(rows.own_part->exchanged(values_of(*miso)));
    for (const auto& start : rows.own_part->shared(row_start, values_of(*miso))) fit_from(start);
  }
  return choose_structures(rows.U, y, usable, std::move(*miso), rows.T_min, rows.bounds,
                           rows.layout, rows.trend, search);
}

// A warm row: the earlier model polished in its structures, then (unless only polished) the
// structure search and the local optima from there.
MisoResult fit_warm(const Rows& rows, const Eigen::VectorXd& y,
                    const std::vector<ElementModel>& start, const StructureSearch& search) {
  MisoResult miso = fit_miso(rows.U, y, rows.screen.usable, start, rows.T_min, rows.bounds,
                             rows.options.max_iterations, rows.layout, rows.trend);
  if (rows.options.start_use == IdentifyOptions::StartUse::first_start) {
    miso = continue_structures(rows.U, y, rows.screen.usable, std::move(miso), rows.T_min,
                               rows.bounds, rows.layout, rows.trend, search);
  }
  return miso;
}

// Row j's model: how well its inputs separate, the gains of inputs that move together and the
// gains near zero profiled (inputs_together.hpp), the projected interval of each gain its
// element's joint region does not tell from zero (gain_profile.hpp), its elements and gain
// covariance written into the model; returns ŷ.
Eigen::VectorXd keep_row(const Rows& rows, int j, const Eigen::VectorXd& y, MisoResult miso,
                         IdentifiedModel& model, OutputFit& fit,
                         const std::vector<RowOptimum>& optima = {}) {
  const std::vector<int>& usable = rows.screen.usable;
  const RowProblem problem{rows.U,      y,           usable,
                           rows.T_min,  rows.bounds, rows.options.max_iterations,
                           rows.layout, rows.trend};
  fit.separation = row_separation(problem, miso);
  fit.inputs_together = describe_together(usable, fit.separation);
  miso = profile_doubtful_gains(problem, std::move(miso), fit.separation);
  cover_other_optima(problem, miso, fit.separation, optima);
  if (rows.options.project_gains)
    project_gains_near_zero(problem, miso, rows.options.projection_scope);
  Eigen::MatrixXd& cov = model.gain_covariance[static_cast<std::size_t>(j)];
  for (std::size_t e = 0; e < usable.size(); ++e) {
    model.element(j, usable[e]) = miso.elements[e];
    for (std::size_t f = 0; f < usable.size(); ++f) {
      cov(usable[e], usable[f]) =
          miso.gain_covariance(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(f));
    }
  }
  fit.iterations = miso.iterations;
  fit.converged = miso.converged;
  return miso.y_hat;
}

// The elements of row j on inputs the screen set aside, with the screen's status and reason.
void mark_screened_out(const InputScreen& screen, int j, IdentifiedModel& model) {
  for (int i = 0; i < model.inputs; ++i) {
    const auto s = static_cast<std::size_t>(i);
    if (screen.status[s] == ElementStatus::identified) continue;
    ElementEstimate& e = model.element(j, i);
    e.value = ElementModel{kNaN, kNaN, kNaN, kNaN};
    e.std_error = e.value;
    e.status = screen.status[s];
    e.reason = screen.reason[s];
  }
}

// One output's fit; writes only its own row of the model and its own OutputFit.
void fit_output(const Rows& rows, int j, IdentificationResult& result) {
  IdentifiedModel& model = result.model;
  const SampleLayout& layout = rows.layout;
  const Eigen::VectorXd y = rows.Y.col(j);
  OutputFit& fit = result.fits[static_cast<std::size_t>(j)];
  const Eigen::VectorXd y_scored = layout.scored_rows(y);
  const double spread = (y_scored.array() - y_scored.mean()).matrix().norm();
  if (spread == 0.0) {
    mark_row(model, j, ElementStatus::output_not_moved,
             "output " + std::to_string(j + 1) + " is constant throughout the scored data");
    fit.fit_percent = kNaN;
    fit.residual_rms = 0.0;
    fit.converged = true;
    return;
  }
  mark_screened_out(rows.screen, j, model);
  // The starts see the output with its least-squares trend removed (the model-free part);
  // the fit itself estimates the trend with the model.
  Eigen::VectorXd y_start = y;
  if (rows.trend.cols() > 0)
    y_start -= rows.trend * (rows.trend.transpose() * layout.weight.cwiseProduct(y));
  StructureSearch search{rows.options.structure, {}, rows.options.max_iterations};
  if (!rows.options.structures.empty()) {
    for (const int i : rows.screen.usable) {
      search.per_element.push_back(
          rows.options.structures[static_cast<std::size_t>(j * rows.n + i)]);
    }
  }
  Eigen::VectorXd y_hat = Eigen::VectorXd::Zero(y.size());
  if (const auto& warm = rows.warm[static_cast<std::size_t>(j)]) {
    y_hat = keep_row(rows, j, y, fit_warm(rows, y, *warm, search), model, fit);
  } else if (!rows.screen.usable.empty()) {
    std::vector<RowOptimum> optima;
    MisoResult miso = fit_cold(rows, y, y_start, search, optima);
    y_hat = keep_row(rows, j, y, std::move(miso), model, fit, optima);
  } else {
    fit.converged = true;
  }
  const Eigen::VectorXd y_hat_scored = layout.scored_rows(y_hat);
  fit.fit_percent = fit_percent(y_scored, y_hat_scored);
  fit.residual_rms =
      (y_hat_scored - y_scored).norm() / std::sqrt(static_cast<double>(y_scored.size()));
  const Eigen::VectorXd residual = y_scored - y_hat_scored;
  std::vector<ElementEstimate*> row;
  for (int i = 0; i < rows.n; ++i) row.push_back(&model.element(j, i));
  if (residual.allFinite() && 2 * kResidualTestLags < residual.size()) {
    fit.residual_tests = residual_tests(residual, rows.U_scored, kResidualTestLags);
  }
  grade_row(row, fit.residual_tests);
  grade_together(row, rows.screen.usable, fit.separation);
}

// Why the model has no finite G(0): the first element not estimated or integrating; "" when
// every gain is estimated and finite.
std::string missing_gain(const IdentifiedModel& model) {
  for (int j = 0; j < model.outputs; ++j) {
    for (int i = 0; i < model.inputs; ++i) {
      const ElementEstimate& e = model.element(j, i);
      const std::string element =
          "element (output " + std::to_string(j + 1) + ", input " + std::to_string(i + 1) + ")";
      if (!e.estimated()) return element + " is " + to_string(e.status) + ": " + e.reason;
      if (e.value.structure == Structure::integrator)
        return element + " integrates: its G(0) is infinite";
    }
  }
  return "";
}

}  // namespace

void analyse_identified_gain(IdentificationResult& result) {
  result.gain.reset();
  result.gain_uncertainty.reset();
  result.gain_unavailable_reason.clear();
  const IdentifiedModel& model = result.model;
  const std::string missing = missing_gain(model);
  if (!missing.empty()) {
    result.gain_unavailable_reason = "G(0) is not finite: " + missing;
    return;
  }
  result.gain = analyse_gain(model.static_gain());
  bool covariance_known = true;
  for (const Eigen::MatrixXd& c : model.gain_covariance) covariance_known &= c.allFinite();
  if (covariance_known) {
    result.gain_uncertainty = gain_uncertainty(model.static_gain(), model.gain_covariance);
  }
}

IdentificationResult identify(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T_min,
                              const SampleLayout& layout, const IdentifyOptions& options) {
  check_arguments(U, Y, T_min, layout, options);
  const Rows rows(U, Y, T_min, layout, options);
  IdentificationResult result;
  IdentifiedModel& model = result.model;
  model.inputs = rows.n;
  model.outputs = rows.p;
  model.sample_time_min = T_min;
  model.elements.assign(static_cast<std::size_t>(rows.n * rows.p), ElementEstimate{});
  model.gain_covariance.assign(static_cast<std::size_t>(rows.p),
                               Eigen::MatrixXd::Constant(rows.n, rows.n, kNaN));
  result.fits.assign(static_cast<std::size_t>(rows.p), OutputFit{});
  // Outputs on min(threads, p) threads (host/process/parallel.hpp); each writes only its own
  // row of the model, so the result does not depend on the thread count.
  parallel_for(rows.p, options.threads, [&](int j) { fit_output(rows, j, result); });
  analyse_identified_gain(result);
  return result;
}

}  // namespace excite::host
