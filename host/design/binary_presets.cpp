// SPDX-License-Identifier: MIT
// Presets 1–8 of Table 6.1: steps and PRBS (host/README.md describes each).

#include <stdexcept>

#include "host/design/composition.hpp"

namespace excite::host {
namespace {

signal::Source step_pair(std::uint32_t start, std::uint32_t window, std::uint32_t step) {
  signal::Source s;
  s.kind = signal::SourceKind::steps;
  s.start = start;
  s.length = window;
  s.steps.segment_count = 2;
  s.steps.segments[0] = {+1.0, step};
  s.steps.segments[1] = {-1.0, step};
  return s;
}

signal::Source prbs(std::uint32_t start, std::uint32_t window, int register_length,
                    std::uint32_t hold, std::uint32_t shift_bits) {
  signal::Source s;
  s.kind = signal::SourceKind::prbs;
  s.start = start;
  s.length = window;
  s.prbs.register_length = static_cast<std::uint8_t>(register_length);
  s.prbs.amplitude = 1.0;
  s.prbs.hold_samples = hold;
  s.prbs.shift = shift_bits;
  return s;
}

// Sequential steps (4.2.1): channel i in slot i of N/m samples: +1 then −1 for one step
// length each, zero for the rest of the slot (the plant settles before the next channel).
void sequential_steps(int channels, const DesignContext& ctx, Composition& comp) {
  const std::uint32_t slot = comp.samples / static_cast<std::uint32_t>(channels);
  const double T = ctx.prior.sample_time_min;
  const auto step = static_cast<std::uint32_t>(
      ctx.prior.step_length_min > 0.0 ? std::lround(ctx.prior.step_length_min / T) : slot / 3U);
  if (step == 0 || 2 * step > slot) {
    throw std::invalid_argument(
        format("step_length_min = %g: two steps of %u samples must fit a slot of %u "
               "samples (%u samples / %d channels)",
               ctx.prior.step_length_min, step, slot, comp.samples, channels));
  }
  for (int i = 0; i < channels; ++i)
    comp.sources.push_back(step_pair(static_cast<std::uint32_t>(i) * slot, slot, step));
  comp.notes.push_back(
      format("sequence: channel i moves in samples [i*%u, (i+1)*%u): +1 for %u, -1 for %u, then 0",
             slot, slot, step, step));
}

// Sequential PRBS: one period of the short sequence per channel, one after another.
void sequential_prbs(int channels, const DesignContext& ctx, Composition& comp) {
  const PrbsDesign& d = ctx.prbs;
  const std::uint32_t period = d.period_bits * d.hold_samples;
  for (int i = 0; i < channels; ++i) {
    comp.sources.push_back(
        prbs(static_cast<std::uint32_t>(i) * period, period, d.register_length, d.hold_samples, 0));
  }
  comp.notes.push_back(
      format("sequence: channel i runs one period (%u samples, n_r = %d) from sample i*%u; zero "
             "after sample %u",
             period, d.register_length, period, period * static_cast<std::uint32_t>(channels)));
}

// Simultaneous uncorrelated PRBS ("cut and shift"): copy j shifted by j·d intervals.
void shifted_prbs(int channels, std::uint32_t start, std::uint32_t window, int register_length,
                  std::uint32_t period_bits, const DesignContext& ctx, Composition& comp) {
  const PrbsDesign& d = ctx.prbs;
  const std::uint32_t shift = channel_shift(d.shift_intervals, period_bits, channels);
  for (int j = 0; j < channels; ++j) {
    comp.sources.push_back(prbs(start, window, register_length, d.hold_samples,
                                static_cast<std::uint32_t>(j) * shift));
  }
  comp.notes.push_back(
      format("cut and shift: %d copies of the n_r = %d sequence (N_s = %u), copy j shifted by j*d, "
             "d = %u switching intervals (D = %.4g)",
             channels, register_length, period_bits, shift, d.shift_intervals));
}

}  // namespace

Eigen::MatrixXd amplitude_matrix(const PriorKnowledge& prior) {
  Eigen::VectorXd a(prior.input_count());
  for (int j = 0; j < prior.input_count(); ++j)
    a(j) = prior.inputs[static_cast<std::size_t>(j)].amplitude;
  return a.asDiagonal();
}

const GainAnalysis& require_gains(const DesignContext& context, std::string_view acronym) {
  if (context.gains == nullptr) {
    throw std::invalid_argument(
        format("gain: missing; preset %.*s uses gain directions and needs G(0)",
               static_cast<int>(acronym.size()), acronym.data()));
  }
  return *context.gains;
}

Composition compose_binary(std::string_view name, const DesignContext& ctx) {
  const int n = ctx.prior.input_count();
  const PrbsDesign& d = ctx.prbs;
  Composition comp;
  comp.samples = d.experiment_samples;
  const bool inputs = name == "stepSeq" || name == "prbsSeq" || name == "prbsUnc";
  if (name == "stepSeq" || name == "stepDir") {
    sequential_steps(n, ctx, comp);
  } else if (name == "prbsSeq" || name == "prbsSeqDir") {
    sequential_prbs(n, ctx, comp);
  } else if (name == "prbsUnc" || name == "prbsSimDir") {
    shifted_prbs(n, 0, comp.samples, d.long_register_length, d.long_period_bits, ctx, comp);
  } else if (name == "prbsDirCorrSeq" || name == "prbsDirCorrSim") {
    const GainAnalysis& g = require_gains(ctx, name);
    const Eigen::VectorXd v_n = g.input_directions.col(g.input_directions.cols() - 1);
    const Eigen::MatrixXd a = amplitude_matrix(ctx.prior);
    comp.mix.resize(n, n + 1);
    comp.mix.leftCols(n) = kCorrelatedLowShare * a;
    comp.mix.col(n) = v_n * (a.diagonal().maxCoeff() / v_n.cwiseAbs().maxCoeff());
    if (name == "prbsDirCorrSeq") {
      // Zhu 2001 ("concatenated"): uncorrelated low-amplitude PRBS on every input in the
      // first half, the high-amplitude PRBS along v_n in the second.
      const std::uint32_t half = comp.samples / 2;
      shifted_prbs(n, 0, half, d.register_length, d.period_bits, ctx, comp);
      comp.sources.push_back(prbs(half, comp.samples - half, d.register_length, d.hold_samples, 0));
      comp.notes.push_back(
          format("Zhu 2001: samples [0, %u) uncorrelated on every input, [%u, %u) along v_n", half,
                 half, comp.samples));
    } else {
      // Zhu 2009 ("combined"): both at once, the v_n signal one more shifted copy.
      shifted_prbs(n + 1, 0, comp.samples, d.long_register_length, d.long_period_bits, ctx, comp);
      comp.notes.push_back(
          "Zhu 2009: the last shifted copy drives v_n, the others the inputs, all at once");
    }
    comp.notes.push_back(
        format("correlated design: uncorrelated amplitude %.3g x the v_n amplitude before scaling",
               kCorrelatedLowShare));
    return comp;
  } else {
    throw std::invalid_argument("preset = \"" + std::string(name) +
                                "\": not a step or PRBS design");
  }
  if (inputs) comp.mix = amplitude_matrix(ctx.prior);
  return comp;
}

}  // namespace excite::host
