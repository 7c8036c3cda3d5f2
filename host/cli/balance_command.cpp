// SPDX-License-Identifier: MIT
// excite balance RUN.csv (--plant NAME | --gain FILE) [--json]: how evenly the outputs of
// an experiment spread over the output gain directions (5.5.2) and Υ (6.2.1).

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/input_path.hpp"
#include "host/cli/json_file.hpp"
#include "host/cli/json_util.hpp"
#include "host/cli/model_file.hpp"
#include "host/cli/run_input.hpp"
#include "host/cli/text_table.hpp"
#include "host/design/case_studies.hpp"
#include "host/identify/balance.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host::cli {
namespace {

struct BalanceOptions {
  std::string run_path;
  std::string plant;
  std::string gain_path;
  bool json = false;
};

constexpr double kMinSingularRatio = 1e-12;  // below: numerically singular

// A gain matrix from JSON with a "gain" array of rows: what `excite gains --json` and
// `excite identify -o` write.
Eigen::MatrixXd read_gain_file(const std::string& path) {
  refuse_directory(path, "a JSON file with \"gain\" (excite gains --json)");
  const nlohmann::json j = read_json_file(path, "a JSON file with \"gain\" (excite gains --json)");
  if (!j.is_object() || !j.contains("gain") || !j["gain"].is_array() || j["gain"].empty()) {
    throw std::invalid_argument(path +
                                ": gain: missing, expected an array of rows (excite gains --json)");
  }
  const auto& rows = j["gain"];
  // Sizes before the allocation: rows × the first row's length, each within a model's limit.
  if (rows.size() > kMaxModelChannels || !rows[0].is_array() ||
      rows[0].size() > kMaxModelChannels) {
    throw std::invalid_argument(path + ": gain = " + std::to_string(rows.size()) + " rows of " +
                                std::to_string(rows[0].size()) + ", expected at most " +
                                std::to_string(kMaxModelChannels) + " x " +
                                std::to_string(kMaxModelChannels) + " (host/README.md, Limits)");
  }
  Eigen::MatrixXd g(static_cast<Eigen::Index>(rows.size()),
                    static_cast<Eigen::Index>(rows[0].size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (!rows[r].is_array() || rows[r].size() != static_cast<std::size_t>(g.cols())) {
      throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "]: expected " +
                                  std::to_string(g.cols()) + " numbers");
    }
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      if (!rows[r][c].is_number()) {
        throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "][" +
                                    std::to_string(c) + "]: expected a number");
      }
      const double v = rows[r][c].get<double>();
      if (!std::isfinite(v)) {
        throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "][" +
                                    std::to_string(c) + "]: expected a finite number");
      }
      g(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = v;
    }
  }
  return g;
}

void run(const BalanceOptions& opt) {
  if (opt.plant.empty() == opt.gain_path.empty())
    throw std::invalid_argument("give exactly one of --plant and --gain");
  const Run data = read_run(opt.run_path);
  const Eigen::MatrixXd gain =
      opt.plant.empty() ? read_gain_file(opt.gain_path) : plant_gain(opt.plant);
  const std::string source = opt.plant.empty() ? opt.gain_path : "plant " + opt.plant;
  if (gain.rows() != data.data.Y.cols() || gain.cols() != data.data.U.cols()) {
    throw std::invalid_argument(
        source + ": gain is " + std::to_string(gain.rows()) + " x " + std::to_string(gain.cols()) +
        ", " + opt.run_path + " has " + std::to_string(data.data.Y.cols()) + " outputs x " +
        std::to_string(data.data.U.cols()) + " inputs; expected outputs x inputs of the run");
  }
  const GainAnalysis a = analyse_gain(gain);
  // A zero singular value leaves its output direction arbitrary: the projections, the ratio
  // and the condition number would mean nothing (or be inf).
  const double sigma_max = a.singular_values.maxCoeff(), sigma_min = a.singular_values.minCoeff();
  if (!(sigma_min > kMinSingularRatio * sigma_max)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  ": gain is singular (smallest singular value %.3g, largest %.3g), expected "
                  "full rank: smallest / largest > %.0e",
                  sigma_min, sigma_max, kMinSingularRatio);
    throw std::invalid_argument(source + text);
  }
  const DirectionalBalance b = directional_balance(data.data.Y, a.output_directions);
  const double upsilon = output_correlation_determinant(data.data.Y);
  if (opt.json) {
    std::cout << nlohmann::json{{"projection_std", to_json(b.std_dev)},
                                {"ratio", to_json(b.ratio)},
                                {"upsilon", to_json(upsilon)}}
                     .dump(2)
              << '\n';
    return;
  }
  TextTable t({"direction", "sigma_i", "std of w_i'y"});
  for (Eigen::Index i = 0; i < b.std_dev.size(); ++i) {
    t.add_row({std::to_string(i + 1), num(a.singular_values(i), 5), num(b.std_dev(i), 5)});
  }
  t.print(std::cout);
  std::cout << "ratio min/max = " << num(b.ratio)
            << " (1: balanced), Upsilon = det(corr(Y)) = " << num(upsilon) << '\n';
}

}  // namespace

void add_balance_command(CLI::App& app) {
  auto opt = std::make_shared<BalanceOptions>();
  CLI::App* cmd =
      app.add_subcommand("balance",
                         "Whether a run moved the outputs as much along the plant's weak gain "
                         "directions as along the strong ones (output balance)");
  cmd->add_option("run", opt->run_path, "run log (CSV)")->required();
  cmd->add_option("--plant", opt->plant, "take the directions from this plant's G(0)");
  cmd->add_option("--gain", opt->gain_path,
                  "take them from a JSON file with \"gain\" (excite gains --json)");
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
