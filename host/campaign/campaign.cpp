// SPDX-License-Identifier: MIT
#include "host/campaign/campaign.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "host/campaign/scored_fit.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/identify/balance.hpp"
#include "host/measures/cross_fit.hpp"
#include "host/measures/input_measures.hpp"
#include "host/process/parallel.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

// The first `rows` rows of `layout` (a gateway's closing ticks past the plan dropped); an
// empty layout is one segment over every row.
SampleLayout first_rows(const SampleLayout& layout, Eigen::Index rows) {
  if (layout.rows() == 0) return SampleLayout::whole(rows);
  if (layout.rows() < rows) {
    throw std::runtime_error("the measured run's layout has " + std::to_string(layout.rows()) +
                             " rows, expected at least the run's " + std::to_string(rows));
  }
  SampleLayout out;
  out.weight = layout.weight.head(rows);
  for (const Segment& s : layout.segments) {
    if (s.begin < rows) out.segments.push_back({s.begin, std::min(s.end, rows)});
  }
  out.check();
  return out;
}

}  // namespace

Balance balance_of(const Eigen::MatrixXd& Y, const GainAnalysis& true_gain) {
  Balance b;
  const DirectionalBalance d = directional_balance(Y, true_gain.output_directions);
  b.projection_std = d.std_dev;
  b.ratio = d.ratio;
  b.upsilon = output_correlation_determinant(Y);
  return b;
}

// One designed experiment run and identified. A plant of its own, so experiments run in
// parallel.
Experiment run_experiment(const Design& design, const PresetInfo& preset,
                          const CampaignOptions& options, double noise_variance,
                          const GainAnalysis& true_gain, double max_time_constant_min) {
  SimulationOptions sim;
  sim.seed = options.seed + static_cast<std::uint64_t>(preset.number);
  sim.noise_variance = 0.0;
  const auto plant = [&options] {
    return options.true_plant ? options.true_plant() : sim::make_plant(options.plant);
  };
  const SimulatedRun clean =
      simulate_plan(*design.plan, std::string(preset.acronym), *plant(), sim);
  sim.noise_variance = noise_variance;
  const std::string name(preset.acronym);
  const MeasuredData measured =
      options.measured_run
          ? options.measured_run({*design.plan, preset.number, name, sim.seed, noise_variance})
          : MeasuredData{simulate_plan(*design.plan, name, *plant(), sim), {}};
  const SimulatedRun& run = measured.run;
  const Eigen::Index rows = clean.du.rows();
  if (run.du.rows() < rows || run.dy.rows() < rows || run.du.cols() != clean.du.cols() ||
      run.dy.cols() != clean.dy.cols()) {
    throw std::runtime_error(name + ": the measured run has " + std::to_string(run.du.rows()) +
                             " rows of " + std::to_string(run.du.cols()) + " inputs and " +
                             std::to_string(run.dy.cols()) + " outputs, expected at least " +
                             std::to_string(rows) + " rows of " + std::to_string(clean.du.cols()) +
                             " and " + std::to_string(clean.dy.cols()));
  }

  Experiment e;
  e.number = preset.number;
  e.name = std::string(preset.acronym);
  e.sample_time_min = run.sample_time_min;
  e.U = run.du.topRows(rows);
  e.Y = run.dy.topRows(rows);
  e.Y_clean = clean.dy;
  e.layout = first_rows(measured.layout, rows);
  e.limit_scale = design.limit_scale;
  const InputMeasures m = measure_inputs(design.table);
  e.cf_avg = m.average.crest_factor;
  e.cf_period_avg = active_crest_factor_avg(design.table);
  e.pips_avg = m.average.pips;
  IdentifyOptions identify_options;
  identify_options.threads = 1;  // the campaign's pool runs experiments in parallel
  identify_options.max_time_constant_min = max_time_constant_min;  // SPEC §6: β·τ_H
  identify_options.structure = options.structure;                  // issue 45
  e.identified = identify(e.U, e.Y, e.sample_time_min, e.layout, identify_options);
  std::vector<double> fits;
  for (const OutputFit& f : e.identified.fits) fits.push_back(f.fit_percent);
  e.fit_avg = mean_finite(fits);
  if (options.truth_known) {
    // The truth's prediction of the run as a model's is scored: from rest at each segment.
    // Simulated here, the measured run is the noise-free one plus noise (same inputs, one
    // segment), so its prediction is Y_clean; any other run is simulated afresh.
    const bool in_process = !options.measured_run;
    e.truth_fit =
        mean_finite(in_process ? scored_fit_of(e.Y_clean, e.Y, e.layout)
                               : truth_fit(*plant(), e.U, e.Y, e.sample_time_min, e.layout));
  }
  e.balance_clean = balance_of(e.Y_clean, true_gain);
  e.balance_noisy = balance_of(scored_about_segment_means(e.Y, e.layout), true_gain);
  return e;
}

namespace {

// SPEC §6: every model on every data set, rows in parallel; the per-model figures as
// cross_validate() gives them (a NaN fit makes that model's cross figures NaN).
void cross_validate_parallel(CampaignResult& result, int threads) {
  const auto R = static_cast<Eigen::Index>(result.experiments.size());
  result.crossfit.resize(R, R);
  parallel_for(static_cast<int>(R), threads, [&](int a) {
    const Experiment& model = result.experiments[static_cast<std::size_t>(a)];
    for (Eigen::Index b = 0; b < R; ++b) {
      const Experiment& data = result.experiments[static_cast<std::size_t>(b)];
      result.crossfit(a, b) = mean_scored_fit(model.identified.model, data.U, data.Y, data.layout);
    }
  });
  Eigen::VectorXd truth(result.truth_known ? R : 0);
  for (Eigen::Index b = 0; b < truth.size(); ++b)
    truth(b) = result.experiments[static_cast<std::size_t>(b)].truth_fit;
  for (Eigen::Index a = 0; a < R; ++a) {
    Experiment& e = result.experiments[static_cast<std::size_t>(a)];
    const CrossFitFigures f = cross_fit_figures(result.crossfit.row(a).transpose(), truth, a);
    e.crossfit_avg = f.average;
    e.crossfit_best = f.best;
    e.crossfit_worst = f.worst;
    e.crossfit_worst_on = static_cast<int>(f.worst_on);
    e.truth_fit_on_worst = f.truth_on_worst;
    e.loss_avg = f.loss_average;
    e.loss_worst = f.loss_worst;
    e.loss_worst_on = static_cast<int>(f.loss_worst_on);
  }
}

}  // namespace

void check_equal_lengths(const std::vector<std::pair<std::string, Eigen::Index>>& lengths,
                         bool allow_unequal, const std::function<void(const std::string&)>& say) {
  bool equal = true;
  std::string list;
  for (const auto& [name, rows] : lengths) {
    equal = equal && rows == lengths.front().second;
    list += (list.empty() ? "" : ", ") + name + " " + std::to_string(rows);
  }
  if (equal) return;
  if (!allow_unequal) {
    throw std::invalid_argument(
        "campaign: the designs differ in length (" + list +
        " samples), expected every design equally long, so that each is judged on as much "
        "data as the others (SPEC §4, thesis §6.3); --allow-unequal-length compares them anyway");
  }
  if (say) {
    say("warning: the designs differ in length (" + list +
        " samples), compared anyway (--allow-unequal-length)");
  }
}

namespace {

using ExperimentReport = std::function<void(const Experiment&)>;

// What a campaign knows before its first run: the plant's channels, the noise, the truth.
CampaignResult new_campaign(const CampaignOptions& options, const sim::Plant& plant,
                            const PriorKnowledge& true_prior) {
  CampaignResult result;
  result.plant = options.plant;
  result.input_names = plant.input_names();
  result.output_names = plant.output_names();
  result.input_units = plant.input_units();
  result.output_units = plant.output_units();
  result.noise_variance = options.noise_variance >= 0.0 ? options.noise_variance
                                                        : case_study_noise_variance(options.plant);
  result.sized_by_static_output = true_prior.sized_by_static_output();
  result.structure = options.structure;
  result.truth_known = options.truth_known;
  result.true_gain = analyse_gain(true_prior.gain);
  return result;
}

// 1. The step test, sized with the prior knowledge's (true) G(0). Designing from its
//    estimate (thesis 6.1.1) needs it first; with the true G(0) it joins the pool. Returns
//    the index of the first pooled design (1 when the step test ran first, else 0).
std::size_t set_design_gain(const CampaignOptions& options, const PriorKnowledge& true_prior,
                            double max_time_constant, CampaignResult& result, PriorKnowledge& prior,
                            const ExperimentReport& report) {
  const auto& all = presets();
  if (options.design_gain == DesignGain::step_test) {
    result.experiments[0] =
        run_experiment(design_preset(true_prior, all.front(), 0), all.front(), options,
                       result.noise_variance, result.true_gain, max_time_constant);
    report(result.experiments[0]);
    const Experiment& step = result.experiments[0];
    if (!step.identified.gain) {
      throw std::invalid_argument("the step test did not identify G(0): " +
                                  step.identified.gain_unavailable_reason);
    }
    result.design_gain = *step.identified.gain;
    result.design_gain_source = "step test (stepSeq)";
    require_full_rank(result.design_gain);
    prior.gain = result.design_gain.gain;
    return 1;
  }
  result.design_gain = result.true_gain;
  result.design_gain_source = "true G(0)";
  return 0;
}

// 2. Every design (the others), in parallel; then their runs and identifications, the
//    longest first so that no long run starts last on an otherwise idle pool.
void run_pooled(const CampaignOptions& options, const PriorKnowledge& prior,
                std::size_t first_pooled, double max_time_constant, CampaignResult& result,
                const std::function<void(const std::string&)>& say,
                const ExperimentReport& report) {
  const auto& all = presets();
  const auto pooled = static_cast<int>(all.size() - first_pooled);
  std::vector<Design> designs(static_cast<std::size_t>(pooled));
  parallel_for(pooled, options.threads, [&](int k) {
    designs[static_cast<std::size_t>(k)] =
        design_preset(prior, all[first_pooled + static_cast<std::size_t>(k)], 0);
  });
  std::vector<std::pair<std::string, Eigen::Index>> lengths;
  if (first_pooled == 1)
    lengths.emplace_back(result.experiments[0].name, result.experiments[0].U.rows());
  for (std::size_t k = 0; k < designs.size(); ++k)
    lengths.emplace_back(std::string(all[first_pooled + k].acronym), designs[k].table.rows());
  check_equal_lengths(lengths, options.allow_unequal_length, say);
  std::vector<int> order(static_cast<std::size_t>(pooled));
  for (int k = 0; k < pooled; ++k) order[static_cast<std::size_t>(k)] = k;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return designs[static_cast<std::size_t>(a)].table.rows() >
           designs[static_cast<std::size_t>(b)].table.rows();
  });
  parallel_for(pooled, options.threads, [&](int slot) {
    const auto k = static_cast<std::size_t>(order[static_cast<std::size_t>(slot)]);
    const std::size_t i = first_pooled + k;
    result.experiments[i] = run_experiment(designs[k], all[i], options, result.noise_variance,
                                           result.true_gain, max_time_constant);
    report(result.experiments[i]);
  });
}

}  // namespace

CampaignResult run_campaign(const CampaignOptions& options,
                            const std::function<void(const std::string&)>& progress) {
  if (options.threads < 1) {
    throw std::invalid_argument("campaign: threads = " + std::to_string(options.threads) +
                                ", expected at least 1");
  }
  std::mutex say_mutex;
  const auto say = [&](const std::string& line) {
    const std::lock_guard<std::mutex> lock(say_mutex);
    if (progress) progress(line);
  };
  const auto plant = sim::make_plant(options.plant);
  const PriorKnowledge true_prior = case_study(options.plant);
  const double max_time_constant = true_prior.beta * true_prior.tau_high_min;  // SPEC §6
  CampaignResult result = new_campaign(options, *plant, true_prior);
  const auto& all = presets();
  const auto total = std::to_string(all.size());
  result.experiments.resize(all.size());
  const ExperimentReport report = [&](const Experiment& e) {
    say("[" + std::to_string(e.number) + "/" + total + "] " + e.name + ": fit " +
        std::to_string(e.fit_avg) + " %, ratio " + std::to_string(e.balance_clean.ratio) +
        " (noise-free)");
  };

  PriorKnowledge prior = true_prior;
  const std::size_t first_pooled =
      set_design_gain(options, true_prior, max_time_constant, result, prior, report);
  run_pooled(options, prior, first_pooled, max_time_constant, result, say, report);
  if (result.experiments[0].identified.gain)
    result.step_gain = *result.experiments[0].identified.gain;

  // 3. Every model on every other experiment's data.
  cross_validate_parallel(result, options.threads);
  say("cross-validated " + std::to_string(all.size()) + " models on " + std::to_string(all.size()) +
      " runs");
  return result;
}

}  // namespace excite::host
