// SPDX-License-Identifier: MIT
// excite validate MODEL RUN.csv [--json]: fit % (5.5.1) of a model on other data; a log with
// flagged rows is scored per segment by identify's rule (segmented_run.hpp), overall and per
// segment.
// excite crossval RUN.csv RUN.csv… [--json]: every run's model on every other run (SPEC §6).

#include <cmath>
#include <filesystem>
#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/json_util.hpp"
#include "host/cli/model_file.hpp"
#include "host/cli/run_input.hpp"
#include "host/cli/run_layout_text.hpp"
#include "host/cli/segmented_run.hpp"
#include "host/cli/text_table.hpp"
#include "host/cli/time_constant_bound.hpp"
#include "host/identify/validate.hpp"

namespace excite::host::cli {
namespace {

struct ValidateOptions {
  std::string model_path;
  std::string run_path;
  bool json = false;
};

// Fit % (5.5.1) per output over the scored rows of [begin, end), the model simulated from
// rest at every segment's start.
std::vector<double> scored_fits(const SegmentedRun& run, const Eigen::MatrixXd& Y_hat,
                                Eigen::Index begin, Eigen::Index end) {
  const SampleLayout& layout = run.data.layout;
  const Eigen::MatrixXd y = scored_rows(run.data.Y, layout, begin, end);
  const Eigen::MatrixXd y_hat = scored_rows(Y_hat, layout, begin, end);
  std::vector<double> fits;
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    fits.push_back(y.rows() > 0 ? fit_percent(y.col(o), y_hat.col(o)) : std::nan(""));
  }
  return fits;
}

void validate_run(const ValidateOptions& opt) {
  ModelChannels channels;
  const IdentifiedModel model = read_model_file(opt.model_path, &channels);
  const SegmentedRun run = read_segmented_run(opt.run_path);
  const runlog::RunLog& log = run.log;
  check_same_channels(channels, opt.model_path, log.input_names, log.output_names, opt.run_path);
  if (std::abs(model.sample_time_min - run.data.sample_time_min) > 1e-9 * model.sample_time_min) {
    throw std::invalid_argument(
        opt.run_path + ": sample_time_min = " + num(run.data.sample_time_min, 6) +
        ", the model's is " + num(model.sample_time_min, 6) + "; expected equal");
  }
  if (run.data.report.scored == 0) {
    throw std::invalid_argument(opt.run_path + ": " + layout_summary(run.data.report, 1) +
                                "; expected rows to score (host/README.md, the flags rule)");
  }
  if (needs_warning(run.data.report)) {
    std::cerr << "excite: warning: " << layout_summary(run.data.report, 1) << '\n';
  }
  const Eigen::MatrixXd Y_hat = simulate_per_segment(model, run.data.U, run.data.layout);
  const std::vector<double> fits = scored_fits(run, Y_hat, 0, run.data.U.rows());
  const std::vector<Segment> segments = scored_segments(run.data.layout);
  if (opt.json) {
    nlohmann::json j = {{"model", opt.model_path}, {"run", opt.run_path}};
    nlohmann::json outs = nlohmann::json::array();
    for (std::size_t o = 0; o < fits.size(); ++o)
      outs.push_back({{"name", log.output_names[o]}, {"fit", to_json(fits[o])}});
    j["outputs"] = outs;
    j["data"] = layout_json(run.data.report, {opt.run_path});
    nlohmann::json per = nlohmann::json::array();
    for (const Segment& s : segments) {
      nlohmann::json f = nlohmann::json::array();
      for (const double v : scored_fits(run, Y_hat, s.begin, s.end)) f.push_back(to_json(v));
      per.push_back({{"first_row", s.begin + 1},
                     {"rows", s.end - s.begin},
                     {"scored_rows", scored_in(run.data.layout, s)},
                     {"fit", f}});
    }
    j["segments"] = per;
    std::cout << j.dump(2) << '\n';
    return;
  }
  TextTable t({"output", "fit %"});
  for (std::size_t o = 0; o < fits.size(); ++o) t.add_row({log.output_names[o], num(fits[o])});
  t.print(std::cout);
  if (segments.size() > 1) {  // the same per segment: where the model holds and where not
    std::vector<std::string> header{"segment", "first row", "rows", "scored"};
    for (const std::string& name : log.output_names) header.push_back("fit % " + name);
    TextTable per(header);
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const Segment& s = segments[k];
      std::vector<std::string> row{std::to_string(k + 1), std::to_string(s.begin + 1),
                                   std::to_string(s.end - s.begin),
                                   std::to_string(scored_in(run.data.layout, s))};
      for (const double v : scored_fits(run, Y_hat, s.begin, s.end)) row.push_back(num(v));
      per.add_row(row);
    }
    std::cout << '\n';
    per.print(std::cout);
  }
}

struct CrossvalOptions {
  std::vector<std::string> runs;
  bool json = false;
  int threads = 2;
  TimeConstantBoundOptions bound;
};

void crossval(const CrossvalOptions& opt) {
  std::vector<IdentifiedModel> models;
  std::vector<Dataset> data;
  std::vector<std::string> names;
  ModelChannels first;  // every run must have the first run's channels, in its order
  for (const std::string& path : opt.runs) {
    const Run r = read_run(path);
    if (path == opt.runs.front()) {
      first = {r.log.input_names, r.log.output_names};
    } else {
      check_same_channels(first, opt.runs.front(), r.log.input_names, r.log.output_names, path);
    }
    IdentifyOptions options;
    options.threads = opt.threads;
    options.max_time_constant_min =
        time_constant_bound(opt.bound, {{path, r.log.plant, r.log.time_scales}}).first;
    models.push_back(identify(r.data.U, r.data.Y, r.data.sample_time_min, options).model);
    names.push_back(std::filesystem::path(path).stem().string());
    data.push_back({names.back(), r.data.U, r.data.Y});
    std::cerr << "identified " << path << '\n';
  }
  const CrossValidation cv = cross_validate(models, data);
  if (opt.json) {
    nlohmann::json j = nlohmann::json::array();
    for (std::size_t a = 0; a < models.size(); ++a) {
      const auto& m = cv.models[a];
      j.push_back({{"name", names[a]},
                   {"fit_own", to_json(m.own)},
                   {"crossfit_avg", to_json(m.cross_average)},
                   {"crossfit_best", to_json(m.cross_best)},
                   {"crossfit_worst", to_json(m.cross_worst)}});
    }
    std::cout << nlohmann::json{{"models", j}, {"fit", rows_to_json(cv.fit)}}.dump(2) << '\n';
    return;
  }
  TextTable t({"model", "own fit %", "cross avg %", "best %", "worst %", "worst on"});
  for (std::size_t a = 0; a < models.size(); ++a) {
    const auto& m = cv.models[a];
    t.add_row({names[a], num(m.own), num(m.cross_average), num(m.cross_best), num(m.cross_worst),
               m.worst_on >= 0 ? names[static_cast<std::size_t>(m.worst_on)] : "-"});
  }
  t.print(std::cout);
}

}  // namespace

void add_validate_commands(CLI::App& app) {
  auto v = std::make_shared<ValidateOptions>();
  CLI::App* cmd =
      app.add_subcommand("validate", "How well a model predicts a run log (fit % per output)");
  cmd->add_option("model", v->model_path, "model file from excite identify -o")->required();
  cmd->add_option("run", v->run_path, "run log (CSV)")->required();
  cmd->add_flag("--json", v->json, "machine-readable output");
  cmd->callback([v] { validate_run(*v); });

  auto c = std::make_shared<CrossvalOptions>();
  CLI::App* cv =
      app.add_subcommand("crossval", "Identify every run, validate every model on every other run");
  cv->add_option("runs", c->runs, "run logs (at least two)")->required()->expected(2, 1 << 16);
  cv->add_flag("--json", c->json, "machine-readable output");
  cv->add_option("--threads", c->threads, "outputs fitted in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  add_time_constant_bound_options(cv, c->bound);
  cv->callback([c] { crossval(*c); });
}

}  // namespace excite::host::cli
