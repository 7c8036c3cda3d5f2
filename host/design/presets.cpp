// SPDX-License-Identifier: MIT
#include "host/design/presets.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "firmware/plan/limits.hpp"
#include "firmware/signal/validate.hpp"
#include "host/design/composition.hpp"
#include "host/design/sizing.hpp"

namespace excite::host {
namespace {

// T_sw of the recipe's first PRBS source (its hold × T), 0 when it has none.
double prbs_switch_time_min(const signal::Recipe& r, double sample_time_min) {
  for (std::uint32_t i = 0; i < r.source_count; ++i) {
    if (r.sources[i].kind == signal::SourceKind::prbs) {
      return r.sources[i].prbs.hold_samples * sample_time_min;
    }
  }
  return 0.0;
}

std::unique_ptr<plan::Plan> make_plan(const PriorKnowledge& prior, const PresetInfo& preset,
                                      const Composition& comp, std::uint64_t created_unix_s) {
  auto p = std::make_unique<plan::Plan>();
  signal::Recipe& r = p->recipe;
  r.channels = static_cast<std::uint32_t>(prior.input_count());
  r.samples = comp.samples;
  if (comp.sources.size() > signal::kMaxSources || comp.lines.size() > signal::kMaxLines) {
    throw std::invalid_argument(
        format("design: %zu sources and %zu multisine lines, expected at most %u and %u",
               comp.sources.size(), comp.lines.size(), signal::kMaxSources, signal::kMaxLines));
  }
  r.source_count = static_cast<std::uint32_t>(comp.sources.size());
  std::copy(comp.sources.begin(), comp.sources.end(), r.sources.begin());
  r.line_count = static_cast<std::uint32_t>(comp.lines.size());
  std::copy(comp.lines.begin(), comp.lines.end(), r.lines.begin());
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
  m.sample_time_min = prior.sample_time_min;
  m.tau_high_min = prior.tau_high_min;
  m.beta = prior.beta;
  m.switch_time_min = prbs_switch_time_min(r, prior.sample_time_min);
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
      {1, "stepSeq", "steps, sequential inputs", ""},
      {2, "stepDir", "steps, sequential gain directions", "stepSeq"},
      {3, "prbsSeq", "PRBS, sequential inputs", ""},
      {4, "prbsUnc", "PRBS, simultaneous uncorrelated inputs", ""},
      {5, "prbsSeqDir", "PRBS, sequential gain directions", "prbsSeq"},
      {6, "prbsSimDir", "PRBS, simultaneous gain directions", "prbsUnc"},
      {7, "prbsDirCorrSeq", "PRBS, uncorrelated then correlated along v_n (Zhu 2001)", "prbsUnc"},
      {8, "prbsDirCorrSim", "PRBS, uncorrelated plus correlated along v_n (Zhu 2009)", "prbsUnc"},
      {9, "msSrdSeq", "Schroeder multisine, sequential inputs", ""},
      {10, "msSrdSeqDir", "Schroeder multisine, sequential gain directions", "msSrdSeq"},
      {11, "msGlmSeq", "Guillaume multisine, sequential inputs", ""},
      {12, "msGlmSeqDir", "Guillaume multisine, sequential gain directions", "msGlmSeq"},
      {13, "msSrdSim", "Schroeder zippered multisine, simultaneous inputs", ""},
      {14, "msSrdSimDir", "Schroeder zippered multisine, simultaneous gain directions", "msSrdSim"},
      {15, "msGlmSim", "Guillaume zippered multisine, simultaneous inputs", ""},
      {16, "msGlmSimDir", "Guillaume zippered multisine, simultaneous gain directions", "msGlmSim"},
      {17, "msGlmZipm", "Guillaume modified zippered multisine, shared lines along v_n",
       "msGlmSim"},
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

namespace {

// The size of a source on its own: 1 for the unit-peak binary sources; for a multisine the
// peak (measure peak) or its RMS over a period, √(Σ a_k²/2) (measure rms).
double source_size(const Composition& comp, std::size_t i, SizeMeasure measure) {
  const signal::Source& s = comp.sources[i];
  if (s.kind != signal::SourceKind::multisine || measure == SizeMeasure::peak) return 1.0;
  double power = 0.0;
  for (std::uint32_t k = 0; k < s.multisine.line_count; ++k) {
    const double a = comp.lines[s.multisine.first_line + k].amplitude;
    power += 0.5 * a * a;
  }
  return std::sqrt(power);
}

// SPEC §3 "Sizing", host/design/sizing.hpp: replaces comp.mix by the static-output size of
// `preset`. Sources 0…n−1 drive input (or direction) i; further sources (correlated designs)
// drive the weakest direction.
void size_by_static_output(const PresetInfo& preset, const GainAnalysis& g, Composition& comp,
                           std::vector<std::string>& notes) {
  const DesignSize& size = design_size(preset.acronym);
  const Eigen::Index n = g.gain.cols();
  const Eigen::VectorXd column_norm = g.gain.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < n; ++j) {
    if (!(column_norm(j) > 0.0)) {
      throw std::invalid_argument(format(
          "gain: column %ld is zero (input %ld moves no output at steady state), expected every "
          "input to have a static effect for sizing = static_output; use input_amplitude",
          static_cast<long>(j), static_cast<long>(j)));
    }
  }
  const auto m = static_cast<Eigen::Index>(comp.sources.size());
  const char* measure = size.measure == SizeMeasure::peak ? "peak" : "RMS";
  const char* origin = size.thesis_value ? "thesis" : "ours, by analogy with prbsDirCorrSim";
  Eigen::MatrixXd mix = Eigen::MatrixXd::Zero(n, m);
  const bool correlated = size.unc > 0.0;
  if (!preset.uses_directions() || correlated) {
    const double c = correlated ? size.unc : size.c;
    for (Eigen::Index j = 0; j < n; ++j) {
      mix(j, j) =
          c / (column_norm(j) * source_size(comp, static_cast<std::size_t>(j), size.measure));
    }
    notes.push_back(format("sizing (SPEC 3): %s of input j = c / |G(0) e_j| with c = %.3g (%s)",
                           measure, c, origin));
  }
  if (correlated) {
    // The further sources together give a static output of RMS c along G(0)·(their mix).
    double power = 0.0;
    for (Eigen::Index i = n; i < m; ++i) {
      const Eigen::VectorXd d = comp.mix.col(i);
      const double s = source_size(comp, static_cast<std::size_t>(i), size.measure);
      power += (g.gain * d).squaredNorm() * s * s;
    }
    const double f = size.c / std::sqrt(power);
    for (Eigen::Index i = n; i < m; ++i) mix.col(i) = f * comp.mix.col(i);
    notes.push_back(
        format("sizing (SPEC 3): the correlated part along v_n gives a static output of %s %.3g, "
               "i.e. c * inv(sigma_n) * v_n (%s)",
               measure, size.c, origin));
  } else if (preset.uses_directions()) {
    for (Eigen::Index i = 0; i < n; ++i) {
      mix.col(i) = g.input_directions.col(i) *
                   (size.c / (g.singular_values(i) *
                              source_size(comp, static_cast<std::size_t>(i), size.measure)));
    }
    notes.push_back(
        format("sizing (SPEC 3, 5.2.2): u = c * V * inv(Sigma) * s, %s of s_i = 1, c = %.3g (%s)",
               measure, size.c, origin));
  }
  comp.mix = mix;
}

// Input limits (per plant, separate from the size): a design that does not fit is scaled
// as a whole, directions preserved; never one channel clipped.
void fit_limits(const PriorKnowledge& prior, const PresetInfo& preset, Composition& comp,
                Design& design, std::uint64_t created_unix_s) {
  const double c = limit_scale(prior, design.table);
  if (c >= 1.0) return;
  comp.mix *= c;
  design.limit_scale = c;
  design.notes.push_back(
      c > 1.0 - 1e-9
          ? format("limits: a peak equal to its limit, scaled by 1 - %.1g against rounding",
                   1.0 - c)
          : format("limits: the design does not fit the input limits; the whole design is "
                   "scaled by %.4g (directions preserved, no channel clipped)",
                   c));
  design.plan = make_plan(prior, preset, comp, created_unix_s);
  design.table = make_table(design.plan->recipe);
}

void check_design_limits(const Design& design) {
  const plan::LimitCheck limits = plan::check_limits(
      *design.plan, signal::ConstTableView(design.table.data(), design.plan->recipe.channels,
                                           design.plan->recipe.samples));
  if (!limits.status)
    throw std::invalid_argument(std::string("design: ") + limits.status.message());
}

}  // namespace

Design design_plain_multisine(const PriorKnowledge& prior, const PlainMultisine& spec,
                              std::uint64_t created_unix_s) {
  validate_inputs(prior);
  Design design;
  Composition comp = compose_plain_multisine(prior, spec);
  design.notes = comp.notes;
  static constexpr PresetInfo kPlain{0, "multisine", "a multisine given by its lines", ""};
  design.plan = make_plan(prior, kPlain, comp, created_unix_s);
  design.table = make_table(design.plan->recipe);
  fit_limits(prior, kPlain, comp, design, created_unix_s);
  check_design_limits(design);
  return design;
}

Design design_preset(const PriorKnowledge& prior, const PresetInfo& preset,
                     std::uint64_t created_unix_s) {
  Design design;
  design.prbs = design_prbs(prior);
  std::unique_ptr<GainAnalysis> gains;
  if (prior.gain.size() != 0) {
    if (prior.gain.rows() != prior.gain.cols() && preset.uses_directions()) {
      throw std::invalid_argument(
          format("gain: %ld x %ld, expected a square matrix for directional designs",
                 static_cast<long>(prior.gain.rows()), static_cast<long>(prior.gain.cols())));
    }
    gains = std::make_unique<GainAnalysis>(analyse_gain(prior.gain));
    if (preset.uses_directions()) require_full_rank(*gains);
  }
  const bool by_output = prior.sized_by_static_output();
  const DesignContext context{prior, design.prbs, gains.get()};
  Composition comp = preset.acronym.starts_with("ms") ? compose_multisine(preset.acronym, context)
                                                      : compose_binary(preset.acronym, context);
  design.notes = design.prbs.explanation;
  design.notes.insert(design.notes.end(), comp.notes.begin(), comp.notes.end());

  if (by_output) {
    if (comp.mix.size() == 0)
      comp.mix = Eigen::MatrixXd::Identity(prior.input_count(), prior.input_count());
    size_by_static_output(preset, *gains, comp, design.notes);
  } else if (comp.mix.size() == 0) {  // gain directions: u = V Σ⁻¹ s (5.2.2)
    const GainAnalysis& g = require_gains(context, preset.acronym);
    comp.mix = g.input_directions * g.singular_values.cwiseInverse().asDiagonal();
    design.notes.push_back(
        "directions: u(k) = c * V * inv(Sigma) * s(k), s_i of unit peak (5.2.2)");
  }
  design.plan = make_plan(prior, preset, comp, created_unix_s);
  design.table = make_table(design.plan->recipe);

  if (!by_output && preset.uses_directions()) {
    // Sized by input amplitude: one common factor c that gives the static outputs the RMS
    // of the corresponding input design.
    const Design ref = design_preset(prior, find_preset(preset.reference), created_unix_s);
    const double c =
        static_output_rms(prior.gain, ref.table) / static_output_rms(prior.gain, design.table);
    design.notes.push_back(
        format("sizing: input amplitudes; c = %.4g gives the static output "
               "RMS of %.*s",
               c, static_cast<int>(preset.reference.size()), preset.reference.data()));
    comp.mix *= c;
    design.plan = make_plan(prior, preset, comp, created_unix_s);
    design.table = make_table(design.plan->recipe);
  }
  fit_limits(prior, preset, comp, design, created_unix_s);
  check_design_limits(design);
  return design;
}

}  // namespace excite::host
