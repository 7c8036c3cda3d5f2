// SPDX-License-Identifier: MIT
#include "host/campaign/closed_loop_experiment.hpp"

#include <vector>

#include "host/campaign/scored_fit.hpp"
#include "host/design/presets.hpp"
#include "host/design/table.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {
namespace {

// Measured rows where an MV sat on its box limit (the run's st columns).
std::size_t mv_limited_rows(const ClosedLoopRecord& record, Eigen::Index rows) {
  std::size_t limited = 0;
  for (Eigen::Index k = 0; k < rows; ++k) {
    bool any = false;
    for (const runlog::MvState st : record.st[static_cast<std::size_t>(k)])
      any |= st != runlog::MvState::ok;
    limited += any ? 1U : 0U;
  }
  return limited;
}

}  // namespace

ClosedLoopRun run_closed_loop_experiment(const Design& design, const PresetInfo& preset,
                                         sim::Plant& plant, sim::control::Controller& controller,
                                         const ClosedLoopExperimentOptions& options,
                                         const GainAnalysis& true_gain) {
  const plan::Plan& plan = *design.plan;
  const std::string name(preset.acronym);
  const Eigen::MatrixXd r = make_table(plan.recipe);
  SimulationOptions clean = options.measured;
  clean.noise_variance = 0.0;
  clean.disturbance_std = 0.0;
  const SimulatedRun quiet = simulate_closed_loop(r, name, plan.meta.sample_time_min, plant,
                                                  controller, options.loop, clean);
  const SimulatedRun run = simulate_closed_loop(r, name, plan.meta.sample_time_min, plant,
                                                controller, options.loop, options.measured);
  ClosedLoopRun out;
  Experiment& e = out.experiment;
  e.number = preset.number;
  e.name = name;
  e.sample_time_min = run.sample_time_min;
  e.U = run.du;
  e.Y = run.dy;
  e.Y_clean = quiet.dy;
  e.layout = SampleLayout::whole(run.du.rows());
  e.limit_scale = design.limit_scale;
  out.R = run.closed_loop->r;
  out.rows_mv_limited = mv_limited_rows(*run.closed_loop, run.du.rows());
  IdentifyOptions identify_options;
  identify_options.threads = 1;  // the caller runs experiments in parallel
  if (options.max_time_constant_min > 0.0)
    identify_options.max_time_constant_min = options.max_time_constant_min;
  // Only the estimate asked for (identify_closed_loop's two fits cost twice as much): the
  // prediction-error fit with its noise model on u (direct) or on stage 1's û (two-stage,
  // its gains and SEs from the instrumental-variable step).
  e.identified =
      options.direct
          ? identify_with_noise_model(e.U, e.Y, e.sample_time_min, e.layout, identify_options)
                .result
          : identify_two_stage(e.U, out.R, e.Y, e.sample_time_min, e.layout, identify_options)
                .fit.result;
  std::vector<double> fits;
  for (const OutputFit& f : e.identified.fits) fits.push_back(f.fit_percent);
  e.fit_avg = mean_finite(fits);
  e.balance_clean = balance_of(e.Y_clean, true_gain);
  e.balance_noisy = balance_of(scored_about_segment_means(e.Y, e.layout), true_gain);
  return out;
}

}  // namespace excite::host
