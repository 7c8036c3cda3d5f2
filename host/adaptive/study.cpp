// SPDX-License-Identifier: MIT
#include "host/adaptive/study.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "base/config/error.hpp"
#include "host/adaptive/closed_loop_adaptive.hpp"
#include "host/adaptive/plant_runner.hpp"
#include "host/adaptive/segments.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/table.hpp"
#include "host/measures/accuracy.hpp"
#include "host/montecarlo/summary.hpp"
#include "host/process/parallel.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/library/library.hpp"
#include "sim/library/perturb.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// max over CVs and rows of dy / limit on its side (0 without limits).
double peak_ratio(const Eigen::MatrixXd& dy, const CvLimits& limits) {
  double peak = 0.0;
  for (Eigen::Index j = 0; j < dy.cols(); ++j) {
    for (Eigen::Index k = 0; k < dy.rows(); ++k) {
      const double y = dy(k, j);
      const double bound = y >= 0.0 ? limits.high(j) : limits.low(j);
      if (std::isfinite(bound)) peak = std::max(peak, y / bound);
    }
  }
  return peak;
}

// The controller file against the nominal plant before any seed runs: a file that does not
// fit (sizes, sample time, its model not integrally controllable for the plant) is refused
// as a whole, so a seed's refusal below can only come from its own plant.
void check_controller_file(const StudyOptions& o) {
  const sim::control::ControllerFile file =
      sim::control::load_controller_file(o.closed_loop->controller);
  const Eigen::MatrixXd g0 = sim::make_plant(o.plant)->static_gain();
  (void)sim::control::make_controller(file, *sim::control::load_model(file), &g0);
  if (!o.adaptive.limits) {
    throw std::invalid_argument(
        "CV limits = none with a controller file, expected --limit (or a DMC file's [[cv]] "
        "limits): r is sized by them");
  }
}

// One seed's test under the controller file's controller; nullopt when the controller
// refuses the seed's plant (`refused` says why).
std::optional<AdaptiveResult> closed_loop_test(const StudyOptions& o, const PriorKnowledge& prior,
                                               sim::Plant& plant, double noise_variance,
                                               std::uint64_t seed, std::string& refused) {
  const ClosedLoopStudyOptions& c = *o.closed_loop;
  const sim::control::ControllerFile file = sim::control::load_controller_file(c.controller);
  const auto model = sim::control::load_model(file);
  const Eigen::MatrixXd g0 = plant.static_gain();
  std::unique_ptr<sim::control::Controller> controller;
  try {
    controller = sim::control::make_controller(file, *model, &g0);
  } catch (const config::Error& e) {
    refused = std::string("the controller refuses this seed's plant: ") + e.what();
    return std::nullopt;
  }
  ClosedLoopOptions loop;
  set_controller(loop, file, std::filesystem::path(c.controller).filename().string());
  SimulationOptions noise;
  noise.seed = seed;
  noise.noise_variance = noise_variance;
  noise.disturbance_std = c.disturbance_std;
  noise.disturbance_tau_min = c.disturbance_tau_min;
  ClosedLoopPlant closed(plant, *controller, loop, noise, prior.sample_time_min);
  ClosedLoopAdaptiveOptions options;
  options.adaptive = o.adaptive;
  options.adaptive.identify.threads = 1;
  options.limit_fraction = c.limit_fraction;
  options.mv_fraction = c.mv_fraction;
  options.two_stage = c.two_stage;
  options.prior_directions = c.prior_directions;
  options.prbs_phase = c.prbs_phase;
  return run_closed_loop_adaptive_test(prior, closed, options);
}

// With the controller on, (4.2.3)'s τ_L for the segments' PRBS: the loop's along the prior's
// weakest output direction (at_the_loops_pace), for the switch segment 0 along the output
// directions gives it.
LoopPace loop_pace(const StudyOptions& o, const PriorKnowledge& prior) {
  const ClosedLoopStudyOptions& c = *o.closed_loop;
  const CvLimits& limits = *o.adaptive.limits;
  const Eigen::VectorXd amplitude = cv_amplitude(limits.low, limits.high, c.limit_fraction);
  return at_the_loops_pace(prior, amplitude, c.mv_fraction,
                           sim::control::load_controller_file(c.controller));
}

SeedOutcome run_seed(const StudyOptions& o, const PriorKnowledge& prior, double noise_variance,
                     std::uint64_t seed) {
  auto plant = true_plant(o.plant, o.perturb_percent, seed);
  const TruePlant truth = true_plant_of(plant->static_gain());
  AdaptiveOptions adaptive = o.adaptive;
  adaptive.identify.threads = 1;
  SeedOutcome s;
  s.seed = seed;
  s.true_sigma_n = truth.gain.singular_values(truth.gain.singular_values.size() - 1);
  AdaptiveResult r;
  if (o.closed_loop) {
    std::optional<AdaptiveResult> closed =
        closed_loop_test(o, prior, *plant, noise_variance, seed, s.stop_reason);
    s.not_run = !closed;
    if (!closed) return s;  // the controller refused this seed's plant
    r = std::move(*closed);
  } else {
    PlantRunner runner(*plant, prior.sample_time_min, noise_variance, seed);
    r = run_adaptive_test(prior, runner, adaptive);
  }

  s.stopped_by_rule = r.criterion_met;
  s.stop_min = r.length_min();
  s.stop_reason = r.stop_reason;
  s.sigma_n_error_at_stop = s.angle_at_stop_deg = kNaN;
  for (const Reestimate& e : r.estimates) {
    const Accuracy a = judge(truth, e.result.gain);
    s.estimate_min.push_back(e.length_min);
    s.estimate_met.push_back(a.met);
    s.estimate_need.push_back(e.confidence.need);
    s.estimate_missing.push_back(e.confidence.missing);
    s.met_at_stop = a.met;
    s.sigma_n_error_at_stop = a.sigma_n_error;
    s.angle_at_stop_deg = a.weakest_angle_deg;
  }
  s.segments = static_cast<int>(r.segments.size());
  for (const SegmentDecision& d : r.segments) {
    if (d.directional) ++s.directional_segments;
    s.smallest_scale = std::min(s.smallest_scale, d.scale);
  }
  if (adaptive.limits) {
    s.peak_limit_ratio = peak_ratio(r.Y_true, *adaptive.limits);
    s.violated = s.peak_limit_ratio > 1.0;
  }
  return s;
}

// The model in force at length L: the latest estimate at or before L.
bool met_at(const SeedOutcome& s, double length_min) {
  bool met = false;
  for (std::size_t i = 0; i < s.estimate_min.size(); ++i) {
    if (s.estimate_min[i] <= length_min + 1e-9) met = s.estimate_met[i];
  }
  return met;
}

}  // namespace

std::unique_ptr<sim::Plant> true_plant(const std::string& plant, double perturb_percent,
                                       std::uint64_t seed) {
  sim::check_perturbable(plant, perturb_percent);
  if (perturb_percent <= 0.0) return sim::make_plant(plant);
  return sim::make_linear_plant(
      plant, sim::perturbed_plant(sim::library_plant(plant), perturb_percent, seed));
}

StudyResult run_study(const StudyOptions& o) {
  if (o.seeds < 1 || o.seeds > 1'000'000) {
    throw std::invalid_argument("seeds = " + std::to_string(o.seeds) + ", expected 1 to 1000000");
  }
  if (o.threads < 1) {
    throw std::invalid_argument("threads = " + std::to_string(o.threads) + ", expected >= 1");
  }
  sim::check_perturbable(o.plant, o.perturb_percent);
  const double noise_variance =
      o.noise_variance >= 0.0 ? o.noise_variance : case_study_noise_variance(o.plant);

  if (o.closed_loop) check_controller_file(o);
  StudyResult result;
  result.options = o;
  PriorKnowledge prior = case_study(o.plant);
  if (o.closed_loop && o.closed_loop->switch_from_loop) {
    const LoopPace pace = loop_pace(o, prior);
    prior = pace.prior;
    result.loop_speed = pace.speed;
  }
  result.tau_low_min = prior.tau_low_min;
  result.seeds.resize(static_cast<std::size_t>(o.seeds));
  parallel_for(o.seeds, o.threads, [&](int i) {
    result.seeds[static_cast<std::size_t>(i)] =
        run_seed(o, prior, noise_variance, o.first_seed + static_cast<std::uint64_t>(i));
  });

  for (const SeedOutcome& s : result.seeds) result.not_run += s.not_run ? 1 : 0;
  const SegmentSources sources = segment_sources(prior);
  result.switch_time_min =
      sources.plain.plan->recipe.sources[0].prbs.hold_samples * prior.sample_time_min;
  result.segment_min =
      whole_bit_rows(*sources.plain.plan, o.adaptive.segment_min > 0.0 ? o.adaptive.segment_min
                                                                       : 4.0 * prior.tau_high_min) *
      prior.sample_time_min;
  double longest = 0.0;
  for (const SeedOutcome& s : result.seeds) longest = std::max(longest, s.stop_min);
  for (double L = result.segment_min; L < longest + result.segment_min - 1e-9;
       L += result.segment_min) {
    const double at = std::min(L, longest);
    result.grid_min.push_back(at);
    int stopped_met = 0, met = 0;
    for (const SeedOutcome& s : result.seeds) {
      if (s.stopped_by_rule && s.met_at_stop && s.stop_min <= at + 1e-9) ++stopped_met;
      if (met_at(s, at)) ++met;
    }
    const double run = std::max(1, o.seeds - result.not_run);
    result.share_stopped_met.push_back(stopped_met / run);
    result.share_met.push_back(met / run);
  }
  for (std::size_t i = 0; i < result.grid_min.size(); ++i) {
    if (result.share_stopped_met[i] >= montecarlo::kT90Share) {
      result.t90_stop = i;
      break;
    }
  }
  result.t90_oracle = montecarlo::t90_index(result.share_met);
  return result;
}

double fixed_design_peak_ratio(const std::string& plant, const std::string& design,
                               const CvLimits& limits, double perturb_percent, std::uint64_t seed) {
  const PriorKnowledge prior = case_study(plant);
  const Design d = design_preset(prior, find_preset(design), 0);
  auto truth = true_plant(plant, perturb_percent, seed);
  const Eigen::MatrixXd du = make_table(d.plan->recipe);
  return peak_ratio(truth->simulate(du, prior.sample_time_min), limits);
}

}  // namespace excite::host
