// SPDX-License-Identifier: MIT
#include "host/campaign/campaign.hpp"

#include <cmath>

#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/identify/balance.hpp"
#include "host/identify/validate.hpp"
#include "host/measures/input_measures.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

double mean_finite(const std::vector<double>& v) {
  double sum = 0.0;
  int n = 0;
  for (const double x : v) {
    if (std::isfinite(x)) {
      sum += x;
      ++n;
    }
  }
  return n > 0 ? sum / n : std::nan("");
}

Experiment run_experiment(const PriorKnowledge& prior, const PresetInfo& preset, sim::Plant& plant,
                          const CampaignOptions& options, const GainAnalysis& true_gain) {
  const Design design = design_preset(prior, preset, 0);
  SimulationOptions sim;
  sim.noise_variance = options.noise_variance >= 0.0 ? options.noise_variance
                                                     : case_study_noise_variance(options.plant);
  sim.seed = options.seed + static_cast<std::uint64_t>(preset.number);
  const SimulatedRun run = simulate_plan(*design.plan, std::string(preset.acronym), plant, sim);

  Experiment e;
  e.number = preset.number;
  e.name = std::string(preset.acronym);
  e.sample_time_min = run.sample_time_min;
  e.U = run.du;
  e.Y = run.dy;
  const InputMeasures m = measure_inputs(design.table);
  e.cf_avg = m.average.crest_factor;
  e.pips_avg = m.average.pips;
  IdentifyOptions identify_options;
  identify_options.threads = options.threads;
  e.identified = identify(e.U, e.Y, e.sample_time_min, identify_options);
  std::vector<double> fits;
  for (const OutputFit& f : e.identified.fits) fits.push_back(f.fit_percent);
  e.fit_avg = mean_finite(fits);
  const DirectionalBalance b = directional_balance(e.Y, true_gain.output_directions);
  e.projection_std = b.std_dev;
  e.ratio = b.ratio;
  e.upsilon = output_correlation_determinant(e.Y);
  return e;
}

}  // namespace

CampaignResult run_campaign(const CampaignOptions& options,
                            const std::function<void(const std::string&)>& progress) {
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  const auto plant = sim::make_plant(options.plant);
  PriorKnowledge prior = case_study(options.plant);
  CampaignResult result;
  result.plant = options.plant;
  result.input_names = plant->input_names();
  result.output_names = plant->output_names();
  result.true_gain = analyse_gain(prior.gain);
  const auto& all = presets();
  const auto total = std::to_string(all.size());

  // 1. The step test: its identified G(0) gives the directions (thesis 6.1.1), unless asked
  //    to use the true one.
  result.experiments.push_back(
      run_experiment(prior, all.front(), *plant, options, result.true_gain));
  const Experiment& step = result.experiments.front();
  say("[1/" + total + "] stepSeq: fit " + std::to_string(step.fit_avg) + " %");
  if (options.true_gain) {
    result.design_gain = result.true_gain;
    result.design_gain_source = "true G(0)";
  } else {
    if (!step.identified.gain) {
      throw std::invalid_argument("the step test did not identify G(0): " +
                                  step.identified.gain_unavailable_reason);
    }
    result.design_gain = *step.identified.gain;
    result.design_gain_source = "step test (stepSeq)";
  }
  require_full_rank(result.design_gain);
  prior.gain = result.design_gain.gain;

  // 2. Every other design with those directions.
  for (std::size_t i = 1; i < all.size(); ++i) {
    result.experiments.push_back(run_experiment(prior, all[i], *plant, options, result.true_gain));
    const Experiment& e = result.experiments.back();
    say("[" + std::to_string(i + 1) + "/" + total + "] " + e.name + ": fit " +
        std::to_string(e.fit_avg) + " %, ratio " + std::to_string(e.ratio));
  }

  // 3. Every model on every other experiment's data.
  std::vector<IdentifiedModel> models;
  std::vector<Dataset> data;
  for (const Experiment& e : result.experiments) {
    models.push_back(e.identified.model);
    data.push_back({e.name, e.U, e.Y});
  }
  const CrossValidation cv = cross_validate(models, data);
  result.crossfit = cv.fit;
  for (std::size_t a = 0; a < result.experiments.size(); ++a) {
    Experiment& e = result.experiments[a];
    e.crossfit_avg = cv.models[a].cross_average;
    e.crossfit_best = cv.models[a].cross_best;
    e.crossfit_worst = cv.models[a].cross_worst;
  }
  say("cross-validated " + std::to_string(models.size()) + " models on " +
      std::to_string(data.size()) + " runs");
  return result;
}

}  // namespace excite::host
