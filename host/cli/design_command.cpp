// SPDX-License-Identifier: MIT
// excite design --plant NAME --preset ACRONYM -o PLAN   (case-study prior knowledge)
// excite design SPEC.toml -o PLAN                       (prior knowledge from a spec)

#include <cstdlib>
#include <ctime>
#include <iostream>
#include <stdexcept>

#include "host/cli/commands.hpp"
#include "host/cli/creation_time.hpp"
#include "host/cli/output_target.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"
#include "host/design/spec.hpp"

namespace excite::host::cli {
namespace {

struct DesignOptions {
  std::string spec;
  std::string plant;
  std::string preset;
  std::string output;
  bool quiet = false;
};

void run(const DesignOptions& opt) {
  refuse_output_among_inputs(opt.output, {opt.spec});
  const HumanTextAside aside(opt.output);
  PriorKnowledge prior;
  std::string preset_name;
  Design design;
  if (!opt.spec.empty()) {
    if (!opt.plant.empty() || !opt.preset.empty()) {
      throw std::invalid_argument("give either SPEC.toml or --plant with --preset, not both");
    }
    DesignSpec spec = load_design_spec(opt.spec);
    prior = std::move(spec.prior);
    preset_name = spec.design;
    if (spec.multisine) design = design_plain_multisine(prior, *spec.multisine, creation_time());
  } else {
    if (opt.plant.empty() || opt.preset.empty()) {
      throw std::invalid_argument("give SPEC.toml, or --plant NAME with --preset ACRONYM");
    }
    prior = case_study(opt.plant);
    preset_name = opt.preset;
  }
  if (!design.plan) design = design_preset(prior, find_preset(preset_name), creation_time());
  write_plan_file(*design.plan, opt.output);
  if (design.limit_scale < 1.0 - 1e-9) {  // said even with --quiet: the size changed
    std::cerr << "note: the design does not fit the input limits; the whole design is scaled by "
              << design.limit_scale << " (directions preserved, no channel clipped)\n";
  }
  if (!opt.quiet) {
    for (const std::string& note : design.notes) std::cout << note << '\n';
    std::cout << "wrote " << opt.output << ": " << preset_name << ", "
              << design.plan->recipe.channels << " channels x " << design.plan->recipe.samples
              << " samples\n";
  }
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto opt = std::make_shared<DesignOptions>();
  CLI::App* cmd = app.add_subcommand("design", "Design an experiment and write its plan file");
  cmd->add_option("spec", opt->spec, "design spec (TOML); see host/README.md")
      ->check(CLI::ExistingFile);
  cmd->add_option("--plant", opt->plant, "library plant whose case-study prior knowledge to use");
  cmd->add_option(
      "--preset", opt->preset,
      "a named design, e.g. prbsSimDir (steps, PRBS or multisines; host/README.md lists them)");
  cmd->add_option("-o,--output", opt->output, "plan file to write")->required();
  cmd->add_flag("-q,--quiet", opt->quiet, "print nothing on success");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
