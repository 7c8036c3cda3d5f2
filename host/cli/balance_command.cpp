// SPDX-License-Identifier: MIT
// excite balance RUN.csv (--plant NAME | --gain FILE) [--json]: how evenly the outputs of
// an experiment spread over the output gain directions (5.5.2) and Υ (6.2.1). A log with
// flagged rows is measured on its scored rows, each segment about its own mean, and per
// segment (identify's rule, host/identify/run_log_input.hpp).

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "host/cli/commands.hpp"
#include "host/cli/run_layout_text.hpp"
#include "host/design/case_studies.hpp"
#include "host/export/json_util.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/balance.hpp"
#include "host/identify/run_log_input.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/output/input_path.hpp"
#include "host/output/json_file.hpp"
#include "host/output/text_table.hpp"

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
      throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "], expected " +
                                  std::to_string(g.cols()) + " numbers");
    }
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      if (!rows[r][c].is_number()) {
        throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "][" +
                                    std::to_string(c) + "], expected a number");
      }
      const double v = rows[r][c].get<double>();
      if (!std::isfinite(v)) {
        throw std::invalid_argument(path + ": gain[" + std::to_string(r) + "][" +
                                    std::to_string(c) + "], expected a finite number");
      }
      g(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = v;
    }
  }
  return g;
}

// The gain the balance is judged against (--plant's or --gain's), checked against the run's
// size and refused when singular: a zero singular value leaves its output direction
// arbitrary, so the projections, the ratio and the condition number would mean nothing.
GainAnalysis checked_gain(const BalanceOptions& opt, const StackedRuns& data) {
  const Eigen::MatrixXd gain =
      opt.plant.empty() ? read_gain_file(opt.gain_path) : plant_gain(opt.plant);
  const std::string source = opt.plant.empty() ? opt.gain_path : "plant " + opt.plant;
  if (gain.rows() != data.Y.cols() || gain.cols() != data.U.cols()) {
    throw std::invalid_argument(
        source + ": gain is " + std::to_string(gain.rows()) + " x " + std::to_string(gain.cols()) +
        ", " + opt.run_path + " has " + std::to_string(data.Y.cols()) + " outputs x " +
        std::to_string(data.U.cols()) + " inputs, expected outputs x inputs of the run");
  }
  GainAnalysis a = analyse_gain(gain);
  const double sigma_max = a.singular_values.maxCoeff(), sigma_min = a.singular_values.minCoeff();
  if (!(sigma_min > kMinSingularRatio * sigma_max)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  ": gain is singular (smallest singular value %.3g, largest %.3g), expected "
                  "full rank: smallest / largest > %.0e",
                  sigma_min, sigma_max, kMinSingularRatio);
    throw std::invalid_argument(source + text);
  }
  return a;
}

// Per segment, what it can say (a short or constant segment has no balance: null / "-").
struct PerSegment {
  Segment s;
  Eigen::Index scored = 0;
  std::optional<DirectionalBalance> balance;
  std::optional<double> upsilon;
};

std::vector<PerSegment> per_segment(const StackedRuns& data, const GainAnalysis& a) {
  std::vector<PerSegment> per;
  for (const Segment& s : scored_segments(data.layout)) {
    const Eigen::MatrixXd part = data.layout.scored_rows(data.Y, s.begin, s.end);
    PerSegment p{s, part.rows(), {}, {}};
    try {  // both measures are about the segment's mean
      p.balance = directional_balance(part, a.output_directions);
      p.upsilon = output_correlation_determinant(part);
    } catch (const std::invalid_argument&) {
    }
    per.push_back(p);
  }
  return per;
}

void print_json(const BalanceOptions& opt, const StackedRuns& data, const DirectionalBalance& b,
                double upsilon, const std::vector<PerSegment>& per) {
  nlohmann::json j{{"projection_std", to_json(b.std_dev)},
                   {"ratio", to_json(b.ratio)},
                   {"upsilon", to_json(upsilon)},
                   {"data", layout_json(data.report, {opt.run_path})}};
  nlohmann::json js = nlohmann::json::array();
  for (const PerSegment& p : per) {
    js.push_back({{"first_row", p.s.begin + 1},
                  {"rows", p.s.end - p.s.begin},
                  {"scored_rows", p.scored},
                  {"projection_std", p.balance ? to_json(p.balance->std_dev) : nullptr},
                  {"ratio", p.balance ? to_json(p.balance->ratio) : nullptr},
                  {"upsilon", p.upsilon ? to_json(*p.upsilon) : nullptr}});
  }
  j["segments"] = js;
  std::cout << j.dump(2) << '\n';
}

void print_text(const GainAnalysis& a, const DirectionalBalance& b, double upsilon,
                const std::vector<PerSegment>& per) {
  TextTable t({"direction", "sigma_i", "std of w_i'y"});
  for (Eigen::Index i = 0; i < b.std_dev.size(); ++i) {
    t.add_row({std::to_string(i + 1), num(a.singular_values(i), 5), num(b.std_dev(i), 5)});
  }
  t.print(std::cout);
  std::cout << "ratio min/max = " << num(b.ratio)
            << " (1: balanced), Upsilon = det(corr(Y)) = " << num(upsilon) << '\n';
  if (per.size() <= 1) return;
  TextTable ts({"segment", "first row", "rows", "scored", "ratio", "Upsilon"});
  for (std::size_t k = 0; k < per.size(); ++k) {
    const PerSegment& p = per[k];
    ts.add_row({std::to_string(k + 1), std::to_string(p.s.begin + 1),
                std::to_string(p.s.end - p.s.begin), std::to_string(p.scored),
                p.balance ? num(p.balance->ratio) : "-", p.upsilon ? num(*p.upsilon) : "-"});
  }
  std::cout << '\n';
  ts.print(std::cout);
}

void run(const BalanceOptions& opt) {
  if (opt.plant.empty() == opt.gain_path.empty())
    throw std::invalid_argument("give exactly one of --plant and --gain");
  const SegmentedRun run = read_segmented_run(opt.run_path);
  const StackedRuns& data = run.data;
  const GainAnalysis a = checked_gain(opt, data);
  if (needs_warning(data.report)) {
    std::cerr << "excite: warning: " << layout_summary(data.report, 1) << '\n';
  }
  // The scored rows of every segment about the segment's own mean, pooled.
  const Eigen::MatrixXd Y = scored_about_segment_means(data.Y, data.layout);
  if (Y.rows() < 2) {
    throw std::invalid_argument(opt.run_path + ": " + layout_summary(data.report, 1) +
                                ", expected at least 2 scored rows");
  }
  const DirectionalBalance b = directional_balance(Y, a.output_directions);
  const double upsilon = output_correlation_determinant(Y);
  const std::vector<PerSegment> per = per_segment(data, a);
  if (opt.json) {
    print_json(opt, data, b, upsilon, per);
  } else {
    print_text(a, b, upsilon, per);
  }
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
