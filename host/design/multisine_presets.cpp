// SPDX-License-Identifier: MIT
// Presets 9–17 of Table 6.1: multisines (SPEC §1, §2, §4; host/README.md).
//   sequential (9–12): A2's standard multisine, one channel at a time, each in its slot of
//                      N/n samples (at least one whole period, filled by continuing it);
//   simultaneous (13–16): A3's zippered spectrum, every channel on its own lines;
//   msGlmZipm (17): A3's modified zippered spectrum, shared lines along v_n.
// Every design lasts the experiment's N samples (the PRBS design's length, SPEC §4: 4080
// in the case study, thesis §6.3 "the same for all cases"): a multisine is continued
// periodically to fill its span, and a period that would not fit is shortened by raising
// ω_L (fitted_request).
// Schroeder (Srd) or Guillaume (Glm) phases; Dir: the channels are gain directions.

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/design/composition.hpp"
#include "host/design/presets.hpp"
#include "host/design/sizing.hpp"
#include "host/multisine/allocation.hpp"
#include "host/multisine/design.hpp"
#include "host/multisine/guillaume.hpp"
#include "host/multisine/phases.hpp"
#include "host/multisine/synthesis.hpp"

namespace excite::host {
namespace {

using multisine::Line;

// Snow (4.4.20, Table 4.4 "amplitude chosen by CF optimizer"): the Guillaume designs get
// n_a high snow slots per channel above the band, filled by the optimiser with at most ρ of
// the band's power. Ours: n_a = 8, ρ = 0.1 lower alatiqi4x4's average crest factor over a
// period from 1.469 to 1.397 (msGlmSim); n_a = 12, ρ = 0.2 gives 1.379 at twice the
// out-of-band power.
constexpr std::uint32_t kHighSnowSlots = 8;
constexpr double kSnowPowerFraction = 0.1;

multisine::GuillaumeOptions snow_options() {
  multisine::GuillaumeOptions options;
  options.snow_power_fraction = kSnowPowerFraction;
  return options;
}

// The Guillaume optimiser's run, as `excite design` shows it (issue 23 §2): its L_p
// schedule, and each channel's crest factor on the optimisation grid from the Schroeder
// start to the result (the optimiser lowers the worst channel's, the objective of
// guillaume.hpp), with the evaluations it took.
multisine::MultisineSet optimised(const multisine::MultisineSet& start,
                                  const multisine::GuillaumeOptions& options, Composition& comp) {
  multisine::GuillaumeReport report;
  multisine::MultisineSet set = multisine::guillaume(start, options, &report);
  std::string schedule, channels;
  for (const double p : options.norms) schedule += format("%s%g", schedule.empty() ? "" : ", ", p);
  double worst_start = 0.0, worst_final = 0.0, mean_start = 0.0, mean_final = 0.0;
  for (std::size_t c = 0; c < report.cf_final.size(); ++c) {
    channels +=
        format("%s%.3f -> %.3f", c == 0 ? "" : ", ", report.cf_start[c], report.cf_final[c]);
    worst_start = std::max(worst_start, report.cf_start[c]);
    worst_final = std::max(worst_final, report.cf_final[c]);
    mean_start += report.cf_start[c] / static_cast<double>(report.cf_final.size());
    mean_final += report.cf_final[c] / static_cast<double>(report.cf_final.size());
  }
  const bool mean = options.aggregate == multisine::ChannelAggregate::mean;
  comp.notes.push_back(format(
      "Guillaume optimiser: L_p norms p = %s, %d L-BFGS iterations each, %u-point grid, %d "
      "evaluations, objective: the %s; worst channel's crest factor %.3f -> %.3f; average %.3f -> "
      "%.3f; per channel (Schroeder start -> result) %s",
      schedule.c_str(), options.iterations_per_norm, report.grid, report.evaluations,
      mean ? "channels' average" : "worst channel", worst_start, worst_final, mean_start,
      mean_final, channels.c_str()));
  return set;
}

std::string snow_note() {
  return format(" with %u high snow slots per channel (at most %.0f %% of the band power)",
                kHighSnowSlots, 100.0 * kSnowPowerFraction);
}

multisine::DesignRequest request(const DesignContext& ctx, std::uint32_t shared_slots) {
  multisine::DesignRequest r;
  r.tau_low = ctx.prior.tau_low_min;
  r.tau_high = ctx.prior.tau_high_min;
  r.alpha = ctx.prior.alpha;
  r.beta = ctx.prior.beta;
  r.channels = static_cast<std::uint32_t>(ctx.prior.input_count());
  r.shared_slots = shared_slots;
  r.sample_time = ctx.prior.sample_time_min;
  r.max_period = static_cast<std::uint32_t>(signal::kTableCapacity / r.channels);
  return r;
}

// Scales the lines so that the sampled signal peaks at exactly 1: a unit-peak source, like
// the ±1 PRBS, so the amplitude matrix gives every design the same input peak.
void normalise_peak(std::vector<Line>& lines, std::uint32_t period) {
  const std::vector<double> x = multisine::synthesize(lines, period);
  double peak = 0.0;
  for (const double v : x) peak = std::max(peak, std::abs(v));
  for (Line& line : lines) line.amplitude /= peak;
}

signal::Source multisine_source(std::uint32_t start, std::uint32_t length, std::uint32_t period,
                                std::uint32_t first_line, std::uint32_t line_count) {
  signal::Source s;
  s.kind = signal::SourceKind::multisine;
  s.start = start;
  s.length = length;
  s.multisine = {period, first_line, line_count};
  return s;
}

std::uint32_t append_lines(Composition& comp, const std::vector<Line>& lines) {
  const auto first = static_cast<std::uint32_t>(comp.lines.size());
  comp.lines.insert(comp.lines.end(), lines.begin(), lines.end());
  return first;
}

std::string crest_factors(const multisine::MultisineSet& set) {
  std::string text;
  for (std::size_t c = 0; c < set.channels.size(); ++c) {
    const double cf = multisine::cf_continuous(multisine::channel_spectrum(set, c), set.period);
    text += format("%s%.3f", c == 0 ? "" : ", ", cf);
  }
  return text;
}

// The request with its period fitted into `span` samples (issue 23 §1): A2's period (4.4.27)
// and A3's (4.4.30) are the smallest ≥ 2π·slots/(T ω_L), ω_L = 1/(β τ_H); when that exceeds
// the span, β is lowered to (span − ½)·T/(2π·slots·τ_H), which makes the period exactly
// `span` (ω_L rises by the ratio; ω_H and with it the band's top stay). A note says so.
multisine::DesignRequest fitted_request(multisine::DesignRequest r, std::uint32_t slots,
                                        std::uint32_t span, const char* what, Composition& comp) {
  if (!(r.sample_time > 0.0)) return r;  // A2/A3 choose T themselves: nothing to fit
  const double period = 2.0 * std::acos(-1.0) * slots * r.beta * r.tau_high / r.sample_time;
  if (period <= static_cast<double>(span)) return r;
  const double beta = (span - 0.5) * r.sample_time / (2.0 * std::acos(-1.0) * slots * r.tau_high);
  comp.notes.push_back(
      format("%s: a period of %.0f samples (beta = %g) does not fit its span of %u samples: beta "
             "lowered to %.4g (omega_L = 1/(beta tau_H) from %.4g to %.4g rad/min), period %u",
             what, std::ceil(period), r.beta, span, beta, 1.0 / (r.beta * r.tau_high),
             1.0 / (beta * r.tau_high), span));
  r.beta = beta;
  return r;
}

// "continued periodically": how a span of `samples` holds a period.
std::string continued(std::uint32_t samples, std::uint32_t period) {
  return format("%u samples = %u whole period%s of %u + %u samples continuing the periodic signal",
                samples, samples / period, samples / period == 1 ? "" : "s", period,
                samples % period);
}

// The zippered set (4.4.18) of the simultaneous designs, with Schroeder or Guillaume phases.
multisine::MultisineSet zippered(bool guillaume, const DesignContext& ctx, Composition& comp,
                                 std::uint32_t& period) {
  const auto n = static_cast<std::uint32_t>(ctx.prior.input_count());
  const multisine::MultisineDesign md = multisine::design_zippered(
      fitted_request(request(ctx, 0), n, comp.samples, "zippered (4.4.30)", comp));
  comp.notes.insert(comp.notes.end(), md.explanation.begin(), md.explanation.end());
  // Guillaume: high snow slots whose amplitudes and phases the optimiser chooses (Table 4.4).
  const std::uint32_t snow = guillaume ? kHighSnowSlots : 0U;
  multisine::MultisineSet set = multisine::zippered_set(md.period, {n, 0, md.lines, snow, 1.0});
  if (guillaume) set = optimised(set, snow_options(), comp);
  comp.notes.push_back(format("zippered (4.4.18), %s phases%s: continuous crest factors %s",
                              guillaume ? "Guillaume" : "Schroeder",
                              guillaume ? snow_note().c_str() : "", crest_factors(set).c_str()));
  period = md.period;
  return set;
}

// Sequential designs (9–12): channel c (an input, or a direction) plays A2's standard
// multisine (4.4.26–4.4.28: the band ω_L … ω_H on one channel, period N_s ≈ 2π β τ_H / T)
// alone in its slot [c·N/n, (c+1)·N/n) — the last slot takes the remainder — the others at
// zero. A slot holds at least one whole period and is filled by continuing the periodic
// signal, not by zeros, so a slot's crest factor is its period's and a channel's crest
// factor over the experiment about √n times that (n = 4: twice, as in the thesis).
void sequential(bool guillaume, const DesignContext& ctx, Composition& comp) {
  const auto n = static_cast<std::uint32_t>(ctx.prior.input_count());
  const std::uint32_t slot = comp.samples / n;
  const multisine::MultisineDesign md = multisine::design_standard(
      fitted_request(request(ctx, 0), 1, slot, "standard multisine (4.4.27)", comp));
  comp.notes.insert(comp.notes.end(), md.explanation.begin(), md.explanation.end());
  multisine::MultisineSet set = multisine::standard_set(1, md.period, 1, md.lines, 1.0);
  if (guillaume) set = optimised(set, {}, comp);
  comp.notes.push_back(format("standard multisine (A2), %s phases: continuous crest factor %s",
                              guillaume ? "Guillaume" : "Schroeder", crest_factors(set).c_str()));
  std::vector<Line> lines = set.channels[0];
  normalise_peak(lines, md.period);
  for (std::uint32_t c = 0; c < n; ++c) {
    const std::uint32_t start = c * slot;
    const std::uint32_t length = c + 1 == n ? comp.samples - start : slot;
    const std::uint32_t first = append_lines(comp, lines);
    comp.sources.push_back(multisine_source(start, length, md.period, first,
                                            static_cast<std::uint32_t>(lines.size())));
  }
  comp.notes.push_back(
      format("sequence: channel i plays alone in samples [i*%u, (i+1)*%u), "
             "the last to %u; a slot: %s",
             slot, slot, comp.samples, continued(slot, md.period).c_str()));
}

// Simultaneous designs (13–16): the zippered channels together over the whole experiment,
// continued periodically past their last whole period.
void simultaneous(bool guillaume, const DesignContext& ctx, Composition& comp) {
  const auto n = static_cast<std::uint32_t>(ctx.prior.input_count());
  std::uint32_t period = 0;
  const multisine::MultisineSet set = zippered(guillaume, ctx, comp, period);
  for (std::uint32_t c = 0; c < n; ++c) {
    std::vector<Line> lines = set.channels[c];
    normalise_peak(lines, period);
    const std::uint32_t first = append_lines(comp, lines);
    comp.sources.push_back(
        multisine_source(0, comp.samples, period, first, static_cast<std::uint32_t>(lines.size())));
  }
  comp.notes.push_back("every channel: " + continued(comp.samples, period));
}

void modified_zippered(const DesignContext& ctx, Composition& comp) {
  const GainAnalysis& g = require_gains(ctx, "msGlmZipm");
  const auto n = static_cast<std::uint32_t>(ctx.prior.input_count());
  const multisine::MultisineDesign md = multisine::design_zippered(
      fitted_request(request(ctx, 1), n + 1, comp.samples, "modified zippered (4.4.30)", comp));
  comp.notes.insert(comp.notes.end(), md.explanation.begin(), md.explanation.end());
  multisine::ModifiedZipperedOptions options;
  options.shared_amplitude = 1.0;
  multisine::MultisineSet set = multisine::modified_zippered_set(
      md.period, {n, 0, md.lines, kHighSnowSlots, kCorrelatedLowShare}, g.gain, options);
  if (ctx.prior.sized_by_static_output()) {
    // The optimiser must see the channels as they will be played: own lines of channel c at
    // RMS c_unc/|G(0) e_c|, the shared lines at RMS c/σ_n (sizing.cpp; presets.cpp then
    // finds nothing left to scale).
    const DesignSize& size = design_size("msGlmZipm");
    const auto scale_to_rms = [](std::vector<Line>& lines, double rms) {
      double power = 0.0;
      for (const Line& line : lines) power += 0.5 * line.amplitude * line.amplitude;
      for (Line& line : lines) line.amplitude *= rms / std::sqrt(power);
    };
    for (std::uint32_t c = 0; c < n; ++c)
      scale_to_rms(set.channels[c], size.unc / g.gain.col(c).norm());
    for (multisine::SharedSource& shared : set.shared) {
      Eigen::VectorXd d(n);
      for (std::uint32_t c = 0; c < n; ++c) d(c) = shared.direction[c];
      scale_to_rms(shared.lines, size.c / ((g.gain * d).norm() *
                                           std::sqrt(static_cast<double>(set.shared.size()))));
    }
  }
  // Issue 23 §2: the shared lines along v_n carry 5-205x each input's own power, and their
  // phases are common to every input, so the worst-input objective held all four inputs at
  // the worst one's crest factor (1.518, 1.532, 1.520, 1.521 on alatiqi4x4). Lowering the
  // inputs' average instead lets the three inputs the shared source dominates most reach
  // 1.41 while u2 (shared power only 5x its own) rises to 1.61: average 1.523 -> 1.461, worst
  // 1.532 -> 1.605 (host/README.md).
  multisine::GuillaumeOptions options_zipm = snow_options();
  options_zipm.aggregate = multisine::ChannelAggregate::mean;
  set = optimised(set, options_zipm, comp);
  const std::string sizes =
      ctx.prior.sized_by_static_output()
          ? std::string(
                "own lines at their played RMS c_unc/|G(0) e_j|, the shared lines along "
                "v_n at c/sigma_n")
          : format("own lines %.3g x the shared lines along v_n", kCorrelatedLowShare);
  comp.notes.push_back(
      format("modified zippered (4.4.21): %s; Guillaume phases%s: continuous crest factors %s",
             sizes.c_str(), snow_note().c_str(), crest_factors(set).c_str()));
  const std::uint32_t window = comp.samples;
  comp.notes.push_back("every source: " + continued(window, md.period));
  comp.mix = Eigen::MatrixXd::Zero(n, n + static_cast<Eigen::Index>(set.shared.size()));
  for (std::uint32_t c = 0; c < n; ++c) {
    const std::uint32_t first = append_lines(comp, set.channels[c]);
    comp.sources.push_back(multisine_source(0, window, md.period, first,
                                            static_cast<std::uint32_t>(set.channels[c].size())));
    comp.mix(c, c) = 1.0;
  }
  for (const multisine::SharedSource& shared : set.shared) {
    const std::uint32_t first = append_lines(comp, shared.lines);
    const auto column = static_cast<Eigen::Index>(comp.sources.size());
    comp.sources.push_back(multisine_source(0, window, md.period, first,
                                            static_cast<std::uint32_t>(shared.lines.size())));
    for (std::uint32_t c = 0; c < n; ++c) comp.mix(c, column) = shared.direction[c];
  }
}

}  // namespace

Composition compose_plain_multisine(const PriorKnowledge& prior, const PlainMultisine& spec) {
  if (spec.last_line < spec.first_line || spec.first_line == 0) {
    throw std::invalid_argument(
        format("multisine.first_line = %u, last_line = %u, expected 1 <= first_line <= last_line",
               spec.first_line, spec.last_line));
  }
  if (spec.periods == 0)
    throw std::invalid_argument("multisine.periods = 0, expected at least one whole period");
  // Sizes first: synthesis and the crest-factor optimisation cost lines x period.
  const std::uint64_t line_count = std::uint64_t{spec.last_line} - spec.first_line + 1;
  if (line_count > signal::kMaxLines) {
    throw std::invalid_argument(
        format("multisine: last_line - first_line + 1 = %llu lines, expected at most %u (the "
               "plan's line table, firmware/signal/recipe.hpp kMaxLines)",
               static_cast<unsigned long long>(line_count), signal::kMaxLines));
  }
  const std::uint64_t samples = std::uint64_t{spec.period} * spec.periods;
  const auto values = samples * static_cast<std::uint64_t>(prior.input_count());
  if (values > signal::kTableCapacity) {
    throw std::invalid_argument(format(
        "multisine: periods x period = %u x %u samples on %zu inputs = %llu values, expected at "
        "most %zu (the gateway's table, firmware/signal/recipe.hpp kTableCapacity)",
        spec.periods, spec.period, static_cast<std::size_t>(prior.input_count()),
        static_cast<unsigned long long>(values), signal::kTableCapacity));
  }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = spec.first_line; i <= spec.last_line; ++i) indices.push_back(i);
  const std::vector<double> amplitudes(indices.size(), 1.0);
  std::vector<double> phases;
  if (spec.phases == "schroeder" || spec.phases == "guillaume") {
    phases = multisine::schroeder_phases(amplitudes);
  } else if (spec.phases == "linear") {
    phases = multisine::linear_phases(indices, spec.period, 0.0);
  } else if (spec.phases == "random") {
    phases = multisine::random_phases(static_cast<std::uint32_t>(indices.size()), spec.seed);
  } else {
    throw std::invalid_argument("multisine.phases = \"" + spec.phases +
                                "\", expected one of: schroeder, linear, random, guillaume");
  }
  std::vector<Line> lines = multisine::make_lines(indices, amplitudes, phases);
  multisine::validate_lines(lines, spec.period, "multisine");
  if (spec.phases == "guillaume") lines = multisine::guillaume(lines, spec.period, {});
  Composition comp;
  comp.notes.push_back(format(
      "%zu lines %u..%u on a %u-sample period, %s phases: sampled crest factor %.3f, "
      "continuous %.3f",
      lines.size(), spec.first_line, spec.last_line, spec.period, spec.phases.c_str(),
      multisine::cf_sampled(lines, spec.period), multisine::cf_continuous(lines, spec.period)));
  normalise_peak(lines, spec.period);
  comp.samples = static_cast<std::uint32_t>(samples);
  const std::uint32_t first = append_lines(comp, lines);
  comp.sources.push_back(multisine_source(0, comp.samples, spec.period, first,
                                          static_cast<std::uint32_t>(lines.size())));
  comp.mix = amplitude_matrix(prior) * Eigen::MatrixXd::Ones(prior.input_count(), 1);
  return comp;
}

Composition compose_multisine(std::string_view name, const DesignContext& ctx) {
  Composition comp;
  comp.samples = ctx.prbs.experiment_samples;
  const bool glm = name.find("Glm") != std::string_view::npos;
  const bool directions = name.ends_with("Dir");
  if (name == "msGlmZipm") {
    modified_zippered(ctx, comp);
    return comp;
  }
  if (name.starts_with("msSrdSeq") || name.starts_with("msGlmSeq")) {
    sequential(glm, ctx, comp);
  } else if (name.starts_with("msSrdSim") || name.starts_with("msGlmSim")) {
    simultaneous(glm, ctx, comp);
  } else {
    throw std::invalid_argument("preset = \"" + std::string(name) + "\": not a multisine design");
  }
  if (!directions) comp.mix = amplitude_matrix(ctx.prior);
  return comp;
}

}  // namespace excite::host
