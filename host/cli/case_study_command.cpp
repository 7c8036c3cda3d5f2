// SPDX-License-Identifier: MIT
// excite case-study --plant NAME [-o DIR]: every preset of Table 6.1 designed with the
// plant's case-study prior knowledge, and their plant-friendliness side by side.

#include <filesystem>
#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/creation_time.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/measures/input_measures.hpp"
#include "host/output/text_table.hpp"

namespace excite::host::cli {
namespace {

struct CaseStudyOptions {
  std::string plant;
  std::string output_dir;
};

void run(const CaseStudyOptions& opt) {
  const PriorKnowledge prior = case_study(opt.plant);
  const GainAnalysis gains = analyse_gain(prior.gain);
  const std::uint64_t created = creation_time();
  if (!opt.output_dir.empty()) std::filesystem::create_directories(opt.output_dir);

  std::cout << "case study " << opt.plant << ": T = " << prior.sample_time_min
            << " min, tau_L = " << prior.tau_low_min << " min, tau_H = " << prior.tau_high_min
            << " min, alpha = " << prior.alpha << ", beta = " << prior.beta
            << "; singular values of G(0):";
  for (Eigen::Index i = 0; i < gains.singular_values.size(); ++i)
    std::cout << ' ' << num(gains.singular_values(i), 5);
  std::cout << " (kappa = " << num(gains.condition_number, 4) << ")\n\n";

  TextTable table({"#", "design", "samples", "CF period", "CF", "PIPS %", "PF", "Phi %", "Phi_i",
                   "RMS", "max|u|", "RMS |G(0)u|", "y min", "y max", "limit scale"});
  std::vector<std::string> range_header{"#", "design"};
  for (const InputSpec& in : prior.inputs) {
    range_header.push_back(in.name + " min");
    range_header.push_back(in.name + " max");
  }
  TextTable ranges(range_header);
  std::vector<std::string> scaled;
  bool first = true;
  for (const PresetInfo& preset : presets()) {
    const Design d = design_preset(prior, preset, created);
    if (first) {
      std::cout << "design procedure A1 (thesis Table 4.2):\n";
      for (std::size_t i = 0; i < d.prbs.explanation.size(); ++i)
        std::cout << "  " << d.prbs.explanation[i] << '\n';
      std::cout << '\n';
      first = false;
    }
    const InputMeasures m = measure_inputs(d.table);
    const Eigen::MatrixXd y = d.table * prior.gain.transpose();
    const double y_rms = std::sqrt(y.rowwise().squaredNorm().mean());
    const double u_peak = d.table.cwiseAbs().maxCoeff();
    table.add_row({std::to_string(preset.number), std::string(preset.acronym),
                   std::to_string(d.plan->recipe.samples), num(active_crest_factor_avg(d.table)),
                   num(m.average.crest_factor), num(m.average.pips), num(m.average.peak_factor),
                   num(m.average.phi), num(m.average.phi_smooth), num(m.average.rms), num(u_peak),
                   num(y_rms), num(y.minCoeff()), num(y.maxCoeff()), num(d.limit_scale)});
    std::vector<std::string> range{std::to_string(preset.number), std::string(preset.acronym)};
    for (const ChannelMeasures& c : m.channels) {
      range.push_back(num(c.min));
      range.push_back(num(c.max));
    }
    ranges.add_row(range);
    if (d.limit_scale < 1.0 - 1e-9) {
      scaled.push_back(std::string(preset.acronym) + " scaled by " + num(d.limit_scale, 4) +
                       " to fit the input limits");
    }
    if (!opt.output_dir.empty()) {
      write_plan_file(
          *d.plan, std::filesystem::path(opt.output_dir) / (std::string(preset.acronym) + ".plan"));
    }
  }
  std::cout << "sizing: "
            << (prior.sized_by_static_output()
                    ? "by static output, the thesis's factor c per design (SPEC 3, "
                      "host/design/sizing.cpp)"
                    : "by input amplitude")
            << "; input limits:";
  for (const InputSpec& in : prior.inputs)
    std::cout << ' ' << in.name << " [" << num(in.min) << ", " << num(in.max) << "]";
  std::cout << "\n\nplant-friendliness, averaged over the inputs (SPEC §5; CF period: over each "
               "input's active span, CF: over the experiment), and the static outputs G(0)u:\n";
  table.print(std::cout);
  std::cout << "\nper-input range of every design:\n";
  ranges.print(std::cout);
  for (const std::string& line : scaled) std::cout << "note: " << line << '\n';
  if (!opt.output_dir.empty()) std::cout << "\nplans written to " << opt.output_dir << "/\n";
}

}  // namespace

void add_case_study_command(CLI::App& app) {
  auto opt = std::make_shared<CaseStudyOptions>();
  CLI::App* cmd =
      app.add_subcommand("case-study", "Design every preset for a library plant and compare them");
  cmd->add_option("--plant", opt->plant, "library plant")->required();
  cmd->add_option("-o,--output-dir", opt->output_dir, "also write each design's plan file here");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
