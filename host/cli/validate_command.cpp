// SPDX-License-Identifier: MIT
// excite validate MODEL RUN.csv [--json]: fit % (5.5.1) of a model on other data.
// excite crossval RUN.csv RUN.csv… [--json]: every run's model on every other run (SPEC §6).

#include <filesystem>
#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/json_util.hpp"
#include "host/cli/model_file.hpp"
#include "host/cli/run_input.hpp"
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

void validate_run(const ValidateOptions& opt) {
  ModelChannels channels;
  const IdentifiedModel model = read_model_file(opt.model_path, &channels);
  const Run data = read_run(opt.run_path);
  check_same_channels(channels, opt.model_path, data.log.input_names, data.log.output_names,
                      opt.run_path);
  if (std::abs(model.sample_time_min - data.data.sample_time_min) > 1e-9 * model.sample_time_min) {
    throw std::invalid_argument(
        opt.run_path + ": sample_time_min = " + num(data.data.sample_time_min, 6) +
        ", the model's is " + num(model.sample_time_min, 6) + "; expected equal");
  }
  const std::vector<double> fits = fit(model, data.data.U, data.data.Y);
  if (opt.json) {
    nlohmann::json j = {{"model", opt.model_path}, {"run", opt.run_path}};
    nlohmann::json outs = nlohmann::json::array();
    for (std::size_t o = 0; o < fits.size(); ++o)
      outs.push_back({{"name", data.log.output_names[o]}, {"fit", to_json(fits[o])}});
    j["outputs"] = outs;
    std::cout << j.dump(2) << '\n';
    return;
  }
  TextTable t({"output", "fit %"});
  for (std::size_t o = 0; o < fits.size(); ++o) t.add_row({data.log.output_names[o], num(fits[o])});
  t.print(std::cout);
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
