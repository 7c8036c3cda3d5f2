// SPDX-License-Identifier: MIT
#include "host/design/presets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "firmware/plan/limits.hpp"
#include "firmware/signal/validate.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {
namespace {

// Low-amplitude share of the correlated designs (Zhu 2009): the uncorrelated PRBS on every
// input has this fraction of the amplitude of the signal along v_n before common scaling.
constexpr double kCorrelatedLowShare = 1.0 / 3.0;

std::string format(const char* fmt, auto... args) {
  char buffer[320];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

// Unit-amplitude scalar sources and the matrix that mixes them into the channels.
struct Composition {
  std::vector<signal::Source> sources;
  Eigen::MatrixXd mix;  // channels × sources
};

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
std::vector<signal::Source> sequential_steps(int channels, std::uint32_t samples,
                                             std::uint32_t step, std::vector<std::string>& notes) {
  const std::uint32_t slot = samples / static_cast<std::uint32_t>(channels);
  if (2 * step > slot) {
    throw std::invalid_argument(
        format("step_length_min: two steps of %u samples do not fit a slot of %u samples (%u "
               "samples / %d channels)",
               step, slot, samples, channels));
  }
  std::vector<signal::Source> sources;
  for (int i = 0; i < channels; ++i)
    sources.push_back(step_pair(static_cast<std::uint32_t>(i) * slot, slot, step));
  notes.push_back(
      format("sequence: channel i moves in samples [i*%u, (i+1)*%u): +1 for %u, -1 for %u, then 0",
             slot, slot, step, step));
  return sources;
}

// Sequential PRBS: one period of the short sequence per channel, one after another.
std::vector<signal::Source> sequential_prbs(int channels, const PrbsDesign& d,
                                            std::vector<std::string>& notes) {
  const std::uint32_t period = d.period_bits * d.hold_samples;
  std::vector<signal::Source> sources;
  for (int i = 0; i < channels; ++i) {
    sources.push_back(
        prbs(static_cast<std::uint32_t>(i) * period, period, d.register_length, d.hold_samples, 0));
  }
  notes.push_back(
      format("sequence: channel i runs one period (%u samples, n_r = %d) from sample i*%u; "
             "zero after sample %u",
             period, d.register_length, period, period * static_cast<std::uint32_t>(channels)));
  return sources;
}

// Simultaneous uncorrelated PRBS: the long sequence, channel j shifted by j·d intervals.
std::vector<signal::Source> shifted_prbs(int channels, std::uint32_t start, std::uint32_t window,
                                         int register_length, std::uint32_t period_bits,
                                         const PrbsDesign& d, std::vector<std::string>& notes) {
  const std::uint32_t shift = channel_shift(d.shift_intervals, period_bits, channels);
  std::vector<signal::Source> sources;
  for (int j = 0; j < channels; ++j) {
    sources.push_back(prbs(start, window, register_length, d.hold_samples,
                           static_cast<std::uint32_t>(j) * shift));
  }
  notes.push_back(
      format("cut and shift: %d copies of the n_r = %d sequence (N_s = %u), copy j shifted by "
             "j*d, d = %u switching intervals (D = %.4g)",
             channels, register_length, period_bits, shift, d.shift_intervals));
  return sources;
}

Eigen::MatrixXd amplitude_matrix(const PriorKnowledge& prior) {
  Eigen::VectorXd a(prior.input_count());
  for (int j = 0; j < prior.input_count(); ++j)
    a(j) = prior.inputs[static_cast<std::size_t>(j)].amplitude;
  return a.asDiagonal();
}

const GainAnalysis& require_gain(const PriorKnowledge& prior, const PresetInfo& preset,
                                 std::unique_ptr<GainAnalysis>& cache) {
  if (prior.gain.size() == 0) {
    throw std::invalid_argument(
        format("gain: missing; preset %.*s uses gain directions and needs G(0)",
               static_cast<int>(preset.acronym.size()), preset.acronym.data()));
  }
  if (prior.gain.rows() != prior.gain.cols()) {
    throw std::invalid_argument(
        format("gain: %ld x %ld, expected a square matrix for directional designs",
               static_cast<long>(prior.gain.rows()), static_cast<long>(prior.gain.cols())));
  }
  if (!cache) cache = std::make_unique<GainAnalysis>(analyse_gain(prior.gain));
  return *cache;
}

std::unique_ptr<plan::Plan> make_plan(const PriorKnowledge& prior, const PresetInfo& preset,
                                      const Composition& comp, std::uint32_t samples,
                                      std::uint64_t created_unix_s) {
  auto p = std::make_unique<plan::Plan>();
  signal::Recipe& r = p->recipe;
  r.channels = static_cast<std::uint32_t>(prior.input_count());
  r.samples = samples;
  if (comp.sources.size() > signal::kMaxSources) {
    throw std::invalid_argument(format("design: %zu sources, expected at most %u",
                                       comp.sources.size(), signal::kMaxSources));
  }
  r.source_count = static_cast<std::uint32_t>(comp.sources.size());
  for (std::size_t i = 0; i < comp.sources.size(); ++i) r.sources[i] = comp.sources[i];
  for (Eigen::Index c = 0; c < comp.mix.rows(); ++c) {
    for (Eigen::Index i = 0; i < comp.mix.cols(); ++i) {
      r.mix[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] = comp.mix(c, i);
    }
  }

  plan::Metadata& m = p->meta;
  plan::set_text(m.design_name, preset.acronym);
  std::string provenance =
      "plant=" + prior.plant + " preset=" + std::string(preset.acronym) + " excite 0.1.0";
  if (provenance.size() >= plan::kProvenanceCapacity)
    provenance.resize(plan::kProvenanceCapacity - 1);
  plan::set_text(m.provenance, provenance);
  m.created_unix_s = created_unix_s;
  m.sample_time_s = prior.sample_time_min * 60.0;
  for (std::size_t j = 0; j < prior.inputs.size(); ++j) {
    const InputSpec& in = prior.inputs[j];
    if (!plan::set_text(m.channels[j].name, in.name)) {
      throw std::invalid_argument(format("inputs[%zu].name = \"%s\", expected at most %zu bytes", j,
                                         in.name.c_str(), plan::kNameCapacity - 1));
    }
    m.channels[j].min = in.min;
    m.channels[j].max = in.max;
  }
  signal::Status status = plan::validate(*p);
  if (status) status = signal::validate(r, signal::kTableCapacity);
  if (!status) throw std::invalid_argument(std::string("plan: ") + status.message());
  return p;
}

// RMS over samples of ‖G(0)·u(k)‖: the size of the static output a table produces.
double static_output_rms(const Eigen::MatrixXd& gain, const Table& table) {
  const Eigen::MatrixXd outputs = table * gain.transpose();
  return std::sqrt(outputs.rowwise().squaredNorm().mean());
}

// Largest c such that c·table stays within every input's limits.
double limit_scale(const PriorKnowledge& prior, const Table& table) {
  double c = std::numeric_limits<double>::infinity();
  for (Eigen::Index j = 0; j < table.cols(); ++j) {
    const InputSpec& in = prior.inputs[static_cast<std::size_t>(j)];
    const double hi = table.col(j).maxCoeff();
    const double lo = table.col(j).minCoeff();
    if (hi > 0.0) c = std::min(c, in.max / hi);
    if (lo < 0.0) c = std::min(c, in.min / lo);
  }
  return c * (1.0 - 1e-12);  // rounding in c·table must not step over a limit
}

}  // namespace

const std::vector<PresetInfo>& presets() {
  static const std::vector<PresetInfo> all = {
      {1, "stepSeq", "steps, sequential inputs", false},
      {2, "stepDir", "steps, sequential gain directions", true},
      {3, "prbsSeq", "PRBS, sequential inputs", false},
      {4, "prbsUnc", "PRBS, simultaneous uncorrelated inputs", false},
      {5, "prbsSeqDir", "PRBS, sequential gain directions", true},
      {6, "prbsSimDir", "PRBS, simultaneous gain directions", true},
      {7, "prbsDirCorrSeq", "PRBS, uncorrelated then correlated along v_n (Zhu 2001)", true},
      {8, "prbsDirCorrSim", "PRBS, uncorrelated plus correlated along v_n (Zhu 2009)", true},
  };
  return all;
}

const PresetInfo& find_preset(std::string_view acronym) {
  for (const PresetInfo& p : presets()) {
    if (p.acronym == acronym) return p;
  }
  std::string known;
  for (const PresetInfo& p : presets())
    known += (known.empty() ? "" : ", ") + std::string(p.acronym);
  throw std::invalid_argument("preset = \"" + std::string(acronym) +
                              "\", expected one of: " + known);
}

Design design_preset(const PriorKnowledge& prior, const PresetInfo& preset,
                     std::uint64_t created_unix_s) {
  Design design;
  design.prbs = design_prbs(prior);
  const PrbsDesign& d = design.prbs;
  design.notes = d.explanation;
  std::vector<std::string>& notes = design.notes;
  const int n = prior.input_count();
  const std::uint32_t samples = d.experiment_samples;
  std::unique_ptr<GainAnalysis> gain_cache;

  const double T = prior.sample_time_min;
  const auto step = static_cast<std::uint32_t>(prior.step_length_min > 0.0
                                                   ? std::lround(prior.step_length_min / T)
                                                   : samples / static_cast<std::uint32_t>(n) / 3U);

  Composition comp;
  std::string_view reference;  // the input design whose output size a directional one matches
  const std::string_view name = preset.acronym;
  if (name == "stepSeq" || name == "stepDir") {
    const bool dir = name == "stepDir";
    comp.sources = sequential_steps(n, samples, step, notes);
    comp.mix = dir ? Eigen::MatrixXd() : amplitude_matrix(prior);
    reference = "stepSeq";
  } else if (name == "prbsSeq" || name == "prbsSeqDir") {
    comp.sources = sequential_prbs(n, d, notes);
    comp.mix = name == "prbsSeq" ? amplitude_matrix(prior) : Eigen::MatrixXd();
    reference = "prbsSeq";
  } else if (name == "prbsUnc" || name == "prbsSimDir") {
    comp.sources =
        shifted_prbs(n, 0, samples, d.long_register_length, d.long_period_bits, d, notes);
    comp.mix = name == "prbsUnc" ? amplitude_matrix(prior) : Eigen::MatrixXd();
    reference = "prbsUnc";
  } else if (name == "prbsDirCorrSeq" || name == "prbsDirCorrSim") {
    const GainAnalysis& g = require_gain(prior, preset, gain_cache);
    const Eigen::VectorXd v_n = g.input_directions.col(g.input_directions.cols() - 1);
    const double a_max = amplitude_matrix(prior).diagonal().maxCoeff();
    comp.mix.resize(n, n + 1);
    comp.mix.leftCols(n) = kCorrelatedLowShare * amplitude_matrix(prior);
    comp.mix.col(n) = v_n * (a_max / v_n.cwiseAbs().maxCoeff());
    if (name == "prbsDirCorrSeq") {
      // Zhu 2001 ("concatenated"): uncorrelated low-amplitude PRBS on every input in the
      // first half, the high-amplitude PRBS along v_n in the second.
      const std::uint32_t half = samples / 2;
      comp.sources = shifted_prbs(n, 0, half, d.register_length, d.period_bits, d, notes);
      comp.sources.push_back(prbs(half, samples - half, d.register_length, d.hold_samples, 0));
      notes.push_back(
          format("Zhu 2001: samples [0, %u) uncorrelated on every input, [%u, %u) along v_n", half,
                 half, samples));
    } else {
      // Zhu 2009 ("combined"): both at once, the v_n signal one more shifted copy.
      comp.sources =
          shifted_prbs(n + 1, 0, samples, d.long_register_length, d.long_period_bits, d, notes);
      notes.push_back(
          "Zhu 2009: the last shifted copy drives v_n, the others the inputs, all at once");
    }
    notes.push_back(
        format("correlated design: uncorrelated amplitude %.3g x the v_n amplitude before scaling",
               kCorrelatedLowShare));
    reference = "prbsUnc";
  } else {
    throw std::invalid_argument("preset = \"" + std::string(name) +
                                "\": not designed by this build");
  }

  if (comp.mix.size() == 0) {  // gain directions: u = V Σ⁻¹ s (5.2.2)
    const GainAnalysis& g = require_gain(prior, preset, gain_cache);
    comp.mix = g.input_directions * g.singular_values.cwiseInverse().asDiagonal();
    notes.push_back("directions: u(k) = c * V * inv(Sigma) * s(k), s_i of unit amplitude (5.2.2)");
  }

  design.plan = make_plan(prior, preset, comp, samples, created_unix_s);
  design.table = make_table(design.plan->recipe);

  if (preset.uses_directions) {
    // One common factor c: the largest that keeps every input within its limits, and no
    // larger than what gives the static outputs the RMS of the corresponding input design.
    const Design ref = design_preset(prior, find_preset(reference), created_unix_s);
    const double c_output =
        static_output_rms(prior.gain, ref.table) / static_output_rms(prior.gain, design.table);
    const double c_limits = limit_scale(prior, design.table);
    const double c = std::min(c_output, c_limits);
    notes.push_back(format(
        "scale: c = min(c_output = %.4g [static output RMS of %.*s], c_limits = %.4g) = %.4g (%s)",
        c_output, static_cast<int>(reference.size()), reference.data(), c_limits, c,
        c_limits < c_output ? "the input limits bind" : "outputs match the input design"));
    comp.mix *= c;
    design.plan = make_plan(prior, preset, comp, samples, created_unix_s);
    design.table = make_table(design.plan->recipe);
  }

  const plan::LimitCheck limits = plan::check_limits(
      *design.plan, signal::ConstTableView(design.table.data(), design.plan->recipe.channels,
                                           design.plan->recipe.samples));
  if (!limits.status)
    throw std::invalid_argument(std::string("design: ") + limits.status.message());
  return design;
}

}  // namespace excite::host
