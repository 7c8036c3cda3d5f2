// SPDX-License-Identifier: MIT
// excite validate MODEL RUN.csv [--json]: fit % (5.5.1) of a model on other data; a log with
// flagged rows is scored per segment by identify's rule (host/identify/run_log_input.hpp), overall
// and per segment. excite crossval RUN.csv RUN.csv… [--json]: every run's model on every other run
// (SPEC §6), every run identified and scored per segment by identify's flags rule.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/run_layout_text.hpp"
#include "host/cli/time_constant_bound.hpp"
#include "host/export/json_util.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/run_log_input.hpp"
#include "host/identify/validate.hpp"
#include "host/output/text_table.hpp"

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
  const Eigen::MatrixXd y = layout.scored_rows(run.data.Y, begin, end);
  const Eigen::MatrixXd y_hat = layout.scored_rows(Y_hat, begin, end);
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
        ", the model's is " + num(model.sample_time_min, 6) + ", expected equal");
  }
  if (run.data.report.scored == 0) {
    throw std::invalid_argument(opt.run_path + ": " + layout_summary(run.data.report, 1) +
                                ", expected rows to score (host/README.md, the flags rule)");
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

// Fit % of `model` on `run`, averaged over the outputs, over the run's scored rows, the
// model from rest at every segment's start (NaN propagates, as in cross_validate).
double average_scored_fit(const IdentifiedModel& model, const SegmentedRun& run) {
  const Eigen::MatrixXd Y_hat = simulate_per_segment(model, run.data.U, run.data.layout);
  const std::vector<double> fits = scored_fits(run, Y_hat, 0, run.data.U.rows());
  double sum = 0.0;
  for (const double v : fits) sum += v;
  return sum / static_cast<double>(fits.size());
}

// Every run identified by identify's flags rule and every model scored on every run's scored
// rows per segment (issue 23 §4); unflagged runs give what cross_validate gave.
void crossval(const CrossvalOptions& opt) {
  std::vector<IdentifiedModel> models;
  std::vector<SegmentedRun> runs;
  std::vector<std::string> names;
  ModelChannels first;  // every run must have the first run's channels, in its order
  for (const std::string& path : opt.runs) {
    runs.push_back(read_segmented_run(path));
    const SegmentedRun& r = runs.back();
    if (path == opt.runs.front()) {
      first = {r.log.input_names, r.log.output_names};
    } else {
      check_same_channels(first, opt.runs.front(), r.log.input_names, r.log.output_names, path);
      if (r.data.sample_time_min != runs.front().data.sample_time_min) {
        throw std::invalid_argument(path + ": sample_time_min = " + num(r.data.sample_time_min, 6) +
                                    ", " + opt.runs.front() + "'s is " +
                                    num(runs.front().data.sample_time_min, 6) + ", expected equal");
      }
    }
    if (needs_warning(r.data.report)) {
      std::cerr << "excite: warning: " << path << ": " << layout_summary(r.data.report, 1) << '\n';
    }
    IdentifyOptions options;
    options.threads = opt.threads;
    options.max_time_constant_min =
        time_constant_bound(opt.bound, {{path, r.log.plant, r.log.time_scales.tau_high_min,
                                         r.log.time_scales.beta}})
            .first;
    models.push_back(
        identify(r.data.U, r.data.Y, r.data.sample_time_min, r.data.layout, options).model);
    names.push_back(std::filesystem::path(path).stem().string());
    std::cerr << "identified " << path << '\n';
  }
  const auto R = static_cast<Eigen::Index>(models.size());
  Eigen::MatrixXd fit(R, R);
  for (Eigen::Index a = 0; a < R; ++a) {
    for (Eigen::Index b = 0; b < R; ++b) {
      fit(a, b) = average_scored_fit(models[static_cast<std::size_t>(a)],
                                     runs[static_cast<std::size_t>(b)]);
    }
  }
  struct PerModel {
    double own = 0.0, average = 0.0, best = -INFINITY, worst = INFINITY;
    int worst_on = -1;
  };
  std::vector<PerModel> per(models.size());
  for (Eigen::Index a = 0; a < R; ++a) {
    PerModel& m = per[static_cast<std::size_t>(a)];
    m.own = fit(a, a);
    double sum = 0.0;
    for (Eigen::Index b = 0; b < R; ++b) {
      if (b == a) continue;
      sum += fit(a, b);
      m.best = std::max(m.best, fit(a, b));
      if (fit(a, b) < m.worst) m.worst = fit(a, b), m.worst_on = static_cast<int>(b);
      if (std::isnan(fit(a, b))) m.best = m.worst = std::nan("");
    }
    m.average = sum / static_cast<double>(R - 1);
  }
  if (opt.json) {
    nlohmann::json j = nlohmann::json::array();
    for (std::size_t a = 0; a < models.size(); ++a) {
      j.push_back({{"name", names[a]},
                   {"fit_own", to_json(per[a].own)},
                   {"crossfit_avg", to_json(per[a].average)},
                   {"crossfit_best", to_json(per[a].best)},
                   {"crossfit_worst", to_json(per[a].worst)}});
    }
    std::cout << nlohmann::json{{"models", j}, {"fit", rows_to_json(fit)}}.dump(2) << '\n';
    return;
  }
  TextTable t({"model", "own fit %", "cross avg %", "best %", "worst %", "worst on"});
  for (std::size_t a = 0; a < models.size(); ++a) {
    const PerModel& m = per[a];
    t.add_row({names[a], num(m.own), num(m.average), num(m.best), num(m.worst),
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
