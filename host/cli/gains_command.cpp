// SPDX-License-Identifier: MIT
// excite gains --plant NAME [--json]: gain-direction analysis of a plant's G(0) (SPEC §3).

#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/case_studies.hpp"
#include "host/export/json_util.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/output/text_table.hpp"

namespace excite::host::cli {
namespace {

struct GainsOptions {
  std::string plant;
  bool json = false;
  double xi_threshold = 10.0;
};

std::string label(const char* prefix, Eigen::Index i) {
  return prefix + std::to_string(i + 1);
}

void print_matrix(std::ostream& out, const char* title, const Eigen::MatrixXd& m,
                  const char* col_prefix) {
  out << title << '\n';
  std::vector<std::string> header{""};
  for (Eigen::Index c = 0; c < m.cols(); ++c) header.push_back(label(col_prefix, c));
  TextTable table(header);
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    std::vector<std::string> row{std::to_string(r + 1)};
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(num(m(r, c), 5));
    table.add_row(row);
  }
  table.print(out);
  out << '\n';
}

void run(const GainsOptions& opt) {
  const GainAnalysis a = analyse_gain(plant_gain(opt.plant));
  if (opt.json) {
    nlohmann::json j;
    j["plant"] = opt.plant;
    j["gain"] = rows_to_json(a.gain);
    j["singular_values"] = to_json(a.singular_values);
    j["condition_number"] = a.condition_number;
    j["xi"] = to_json(a.xi);
    j["rga"] = rows_to_json(a.rga);
    j["input_directions"] = columns_to_json(a.input_directions);
    j["output_directions"] = columns_to_json(a.output_directions);
    j["weak_directions"] = a.weak_directions(opt.xi_threshold);
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::cout << "plant " << opt.plant << ": G(0) = W Sigma V^T (5.2.1)\n\n";
  print_matrix(std::cout, "G(0) (rows: outputs, columns: inputs)", a.gain, "u");
  TextTable sv({"direction", "sigma", "xi = sigma_1/sigma_i", "needs excitation"});
  const auto weak = a.weak_directions(opt.xi_threshold);
  for (Eigen::Index i = 0; i < a.singular_values.size(); ++i) {
    const bool is_weak = std::find(weak.begin(), weak.end(), static_cast<int>(i)) != weak.end();
    sv.add_row({std::to_string(i + 1), num(a.singular_values(i), 5), num(a.xi(i), 5),
                is_weak ? "yes (xi >= " + num(opt.xi_threshold, 3) + ")" : "-"});
  }
  sv.print(std::cout);
  std::cout << "condition number kappa = " << num(a.condition_number, 5) << "\n\n";
  print_matrix(std::cout, "input directions V (column i is v_i)", a.input_directions, "v");
  print_matrix(std::cout, "output directions W (column i is w_i)", a.output_directions, "w");
  print_matrix(std::cout, "relative gain array", a.rga, "u");
}

}  // namespace

void add_gains_command(CLI::App& app) {
  auto opt = std::make_shared<GainsOptions>();
  CLI::App* cmd = app.add_subcommand("gains",
                                     "How differently the plant responds in its input directions: "
                                     "principal gains, condition number, RGA");
  cmd->add_option("--plant", opt->plant, "library plant name")->required();
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->add_option("--xi-threshold", opt->xi_threshold, "xi from which a direction needs excitation")
      ->capture_default_str()
      ->check(finite_number(1.0, false, "a finite number >= 1 (xi_1 = 1)"));
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
