// SPDX-License-Identifier: MIT
// excite inspect PLAN... [--json] [--plant NAME]: each plan's metadata, the
// plant-friendliness of its table (SPEC §5, with every input's min and max) and, given a
// plant, the predicted static output excursions. Several plans: then one table of every
// design's per-input min and max, side by side.

#include <Eigen/QR>

#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cli/commands.hpp"
#include "host/cli/input_table.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/continuous_crest.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/table.hpp"
#include "host/export/json_util.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/output/text_table.hpp"

namespace excite::host::cli {
namespace {

struct InspectOptions {
  std::vector<std::string> plan_paths;
  std::string plant;
  bool json = false;
};

// What a plan predicts on --plant: the static MV moves of setpoint excitation, or the
// static output excursions of an open-loop or MV plan.
struct Predicted {
  Eigen::MatrixXd static_mv;  // MVs × samples; empty unless setpoint excitation on --plant
  std::vector<OutputExcursion> excursions;
};

nlohmann::json plan_json(const std::string& plan_path, const plan::Plan& p,
                         const InputMeasures& measures, const std::vector<std::string>& names,
                         const std::vector<double>& cf_continuous, const Predicted& predicted) {
  const plan::Excitation excitation = p.meta.excitation;
  const Eigen::MatrixXd& static_mv = predicted.static_mv;
  const std::vector<OutputExcursion>& excursions = predicted.excursions;
  nlohmann::json j = input_measures_json(measures, names, cf_continuous);
  j["plan"] = plan_path;
  j["design"] = std::string(plan::text_of(p.meta.design_name));
  j["provenance"] = std::string(plan::text_of(p.meta.provenance));
  j["samples"] = p.recipe.samples;
  j["sample_time_min"] = p.meta.sample_time_min;
  if (excitation != plan::Excitation::open_loop) j["excitation"] = plan::to_text(excitation);
  if (static_mv.size() != 0) {
    nlohmann::json mv = nlohmann::json::array();
    for (Eigen::Index i = 0; i < static_mv.rows(); ++i) {
      mv.push_back({{"min", static_mv.row(i).minCoeff()}, {"max", static_mv.row(i).maxCoeff()}});
    }
    j["static_mv_moves"] = mv;
  }
  if (!excursions.empty()) {
    nlohmann::json ex = nlohmann::json::array();
    for (const OutputExcursion& e : excursions) ex.push_back({{"min", e.min}, {"max", e.max}});
    j["static_output_excursions"] = ex;
  }
  return j;
}

void print_plan(const InspectOptions& opt, const std::string& plan_path, const plan::Plan& p,
                const InputMeasures& measures, const std::vector<std::string>& names,
                const std::vector<double>& cf_continuous, const Predicted& predicted) {
  const plan::Excitation excitation = p.meta.excitation;
  const bool setpoint = excitation == plan::Excitation::setpoint;
  const Eigen::MatrixXd& static_mv = predicted.static_mv;
  const std::vector<OutputExcursion>& excursions = predicted.excursions;
  std::cout << "plan " << plan_path << ": " << plan::text_of(p.meta.design_name) << " ("
            << plan::text_of(p.meta.provenance) << ")\n"
            << p.recipe.channels << " channels x " << p.recipe.samples << " samples of "
            << num(p.meta.sample_time_min) << " min, " << p.recipe.source_count << " sources\n";
  if (setpoint) {
    std::cout << "closed loop, setpoint excitation: the table is r, offsets of the CV "
                 "setpoints (CV units); the channels are CVs\n";
  } else if (excitation == plan::Excitation::mv) {
    std::cout << "closed loop, MV dither: the table is added to the controller's MV output\n";
  }
  std::cout << '\n';
  print_input_measures(std::cout, measures, names, cf_continuous);
  if (static_mv.size() != 0) {
    std::cout << "\npredicted static MV moves G(0)^-1 r(k) on " << opt.plant
              << " (what the plant sees once the controller's integral action has settled):\n";
    TextTable out({"MV", "min", "max"});
    for (Eigen::Index i = 0; i < static_mv.rows(); ++i) {
      out.add_row({"u" + std::to_string(i + 1), num(static_mv.row(i).minCoeff(), 4),
                   num(static_mv.row(i).maxCoeff(), 4)});
    }
    out.print(std::cout);
  }
  if (!excursions.empty()) {
    std::cout << "\npredicted static output excursions G(0)*u(k) on " << opt.plant << ":\n";
    TextTable out({"output", "min", "max"});
    for (std::size_t i = 0; i < excursions.size(); ++i) {
      out.add_row({"y" + std::to_string(i + 1), num(excursions[i].min), num(excursions[i].max)});
    }
    out.print(std::cout);
  }
}

// One plan; returns its table's measures for the side-by-side summary.
nlohmann::json inspect_one(const InspectOptions& opt, const std::string& plan_path,
                           InputMeasures& measures_out, std::vector<std::string>& names_out,
                           std::string& design_out) {
  const auto p = read_plan_file(plan_path);
  const Table table = make_table(p->recipe);
  const InputMeasures measures = measure_inputs(table);
  measures_out = measures;
  design_out = std::string(plan::text_of(p->meta.design_name));
  const std::vector<double> cf_continuous = continuous_crest_factors(p->recipe, table);
  std::vector<std::string> names;
  for (std::uint32_t c = 0; c < p->recipe.channels; ++c)
    names.emplace_back(plan::text_of(p->meta.channels[c].name));
  names_out = names;

  const plan::Excitation excitation = p->meta.excitation;
  const bool setpoint = excitation == plan::Excitation::setpoint;
  // Setpoint excitation: what the plant sees is u ≈ G(0)⁻¹ r under integral action (the
  // static MV moves), not G(0)·r.
  Predicted predicted;
  if (!opt.plant.empty() && setpoint) {
    const Eigen::MatrixXd g = plant_gain(opt.plant);
    if (g.rows() != static_cast<Eigen::Index>(p->recipe.channels)) {
      throw std::invalid_argument(plan_path + ": channels = " + std::to_string(p->recipe.channels) +
                                  ", expected the " + std::to_string(g.rows()) + " CVs of " +
                                  opt.plant + " (a setpoint plan)");
    }
    predicted.static_mv = g.completeOrthogonalDecomposition().pseudoInverse() * table.transpose();
  } else if (!opt.plant.empty()) {
    predicted.excursions = static_output_excursions(plant_gain(opt.plant), table);
  }
  if (opt.json) return plan_json(plan_path, *p, measures, names, cf_continuous, predicted);
  print_plan(opt, plan_path, *p, measures, names, cf_continuous, predicted);
  return nullptr;
}

void run(const InspectOptions& opt) {
  nlohmann::json all = nlohmann::json::array();
  std::vector<std::string> designs;
  std::vector<InputMeasures> measures(opt.plan_paths.size());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < opt.plan_paths.size(); ++i) {
    if (i > 0 && !opt.json) std::cout << '\n';
    std::string design;
    all.push_back(inspect_one(opt, opt.plan_paths[i], measures[i], names, design));
    designs.push_back(design);
  }
  if (opt.json) {
    std::cout << (all.size() == 1 ? all.front() : all).dump(2) << '\n';
    return;
  }
  if (opt.plan_paths.size() < 2) return;
  std::vector<std::string> header{"design"};
  for (const std::string& name : names) {
    header.push_back(name + " min");
    header.push_back(name + " max");
  }
  TextTable ranges(header);
  for (std::size_t i = 0; i < designs.size(); ++i) {
    std::vector<std::string> row{designs[i]};
    for (const ChannelMeasures& c : measures[i].channels) {
      row.push_back(num(c.min));
      row.push_back(num(c.max));
    }
    row.resize(header.size(), "-");  // plans with fewer channels than the last one
    ranges.add_row(row);
  }
  std::cout << "\nper-input min and max of every design:\n";
  ranges.print(std::cout);
}

}  // namespace

void add_inspect_command(CLI::App& app) {
  auto opt = std::make_shared<InspectOptions>();
  CLI::App* cmd = app.add_subcommand("inspect",
                                     "How gentle a plan is on the plant: move sizes, amplitudes "
                                     "and the static output swing it causes");
  cmd->add_option("plan", opt->plan_paths, "plan file(s)")->required();
  cmd->add_option("--plant", opt->plant,
                  "library plant: also predict the static output excursions");
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
