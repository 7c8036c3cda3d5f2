// SPDX-License-Identifier: MIT
#include "host/design/presets.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "firmware/plan/limits.hpp"
#include "firmware/signal/validate.hpp"
#include "host/design/composition.hpp"

namespace excite::host {
namespace {

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

Design design_plain_multisine(const PriorKnowledge& prior, const PlainMultisine& spec,
                              std::uint64_t created_unix_s) {
  validate_inputs(prior);
  Design design;
  const Composition comp = compose_plain_multisine(prior, spec);
  design.notes = comp.notes;
  static constexpr PresetInfo kPlain{0, "multisine", "a multisine given by its lines", ""};
  design.plan = make_plan(prior, kPlain, comp, created_unix_s);
  design.table = make_table(design.plan->recipe);
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
  const DesignContext context{prior, design.prbs, gains.get()};
  Composition comp = preset.acronym.starts_with("ms") ? compose_multisine(preset.acronym, context)
                                                      : compose_binary(preset.acronym, context);
  design.notes = design.prbs.explanation;
  design.notes.insert(design.notes.end(), comp.notes.begin(), comp.notes.end());

  if (comp.mix.size() == 0) {  // gain directions: u = V Σ⁻¹ s (5.2.2)
    const GainAnalysis& g = require_gains(context, preset.acronym);
    comp.mix = g.input_directions * g.singular_values.cwiseInverse().asDiagonal();
    design.notes.push_back(
        "directions: u(k) = c * V * inv(Sigma) * s(k), s_i of unit peak (5.2.2)");
  }
  design.plan = make_plan(prior, preset, comp, created_unix_s);
  design.table = make_table(design.plan->recipe);

  if (preset.uses_directions()) {
    // One common factor c: the largest that keeps every input within its limits, and no
    // larger than what gives the static outputs the RMS of the corresponding input design.
    const Design ref = design_preset(prior, find_preset(preset.reference), created_unix_s);
    const double c_output =
        static_output_rms(prior.gain, ref.table) / static_output_rms(prior.gain, design.table);
    const double c_limits = limit_scale(prior, design.table);
    const double c = std::min(c_output, c_limits);
    design.notes.push_back(format(
        "scale: c = min(c_output = %.4g [static output RMS of %.*s], c_limits = %.4g) = %.4g "
        "(%s)",
        c_output, static_cast<int>(preset.reference.size()), preset.reference.data(), c_limits, c,
        c_limits < c_output ? "the input limits bind" : "outputs match the input design"));
    comp.mix *= c;
    design.plan = make_plan(prior, preset, comp, created_unix_s);
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
