// SPDX-License-Identifier: MIT
// excite campaign --plant NAME -o DIR [--design-gain true|step-test] [--noise-var V] [--seed S]
//                 [--threads N] [--loop] [--overwrite] [--allow-unequal-length]
//                 [--structure auto|NAME]
// excite campaign --plant NAME --controller FILE -o DIR [--loop] [--excitation setpoint|mv]
//                 [--limit CV=LO:HI ...] [--limit-fraction F] [--mv-fraction F] [--designs A,B]
//                 [--directions none|output] [--switching loop|plant]
//                 [--open-loop-report PATH]
//   the campaign with the controller on (issue 42 §4, host/loop/closed_loop_campaign.hpp):
//   the closed-loop designs (every plain preset, setpoint excitation or MV dither), each run
//   closed loop (--loop: through the real gateway to excite-plant --controller; else in
//   process), identified two-stage; DIR/summary.json, DIR/index.html, models/, runs/.
// The chapter-6 study: DIR/summary.json, the report DIR/index.html, every identified model
// in DIR/models/NN-name.json and every measured run's log in DIR/runs/NN-name/run.csv, both
// linked from the report. With --loop every plan is streamed through the real
// excite-gateway to the real excite-plant (host/loop), and DIR/runs/NN-name/ also keeps the
// plan, the configuration pair and the plant's log.
// DIR is written whole (host/output/whole_folder.hpp): checked before any work (a new or
// empty folder, a previous campaign's, or --overwrite), filled as a temporary sibling and
// renamed into place at the end, so a failed or interrupted run leaves the previous report.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "firmware/runlog/format.hpp"
#include "host/adaptive/cv_limit_text.hpp"
#include "host/campaign/campaign.hpp"
#include "host/campaign/report.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/plan_file.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/element.hpp"
#include "host/loop/campaign_runs.hpp"
#include "host/loop/closed_loop_campaign.hpp"
#include "host/loop/closed_loop_campaign_report.hpp"
#include "host/output/whole_file.hpp"
#include "host/output/whole_folder.hpp"
#include "host/simulate/simulate.hpp"

namespace excite::host::cli {
namespace {

namespace fs = std::filesystem;

struct CampaignCommandOptions {
  CampaignOptions campaign;
  std::string structure = "auto";  // or a name excite identify --structure takes
  std::string output_dir;
  bool loop = false;
  bool overwrite = false;
  // With the controller on (issue 42 §4).
  std::string controller;
  std::string excitation = "setpoint";
  std::vector<std::string> limits;  // CV=LO:HI
  double limit_fraction = 0.5;
  double mv_fraction = 0.0;
  std::string directions = "none";
  std::string switching = "loop";  // setpoint: (4.2.3)'s τ_L the loop's or the plant's
  std::vector<std::string> designs;
  std::string open_loop_report;
};

// DIR/models/NN-name.json, one per experiment; returns their paths relative to DIR.
std::vector<std::string> write_models(const CampaignResult& result, const fs::path& dir) {
  fs::create_directories(dir / "models");
  std::vector<std::string> written;
  for (const Experiment& e : result.experiments) {
    const std::string relative = "models/" + experiment_folder(e.number, e.name) + ".json";
    write_whole_file(
        dir / relative,
        model_json(e.identified, result.input_names, result.output_names).dump(2) + "\n");
    written.push_back(relative);
  }
  return written;
}

// DIR/runs/NN-name/run.csv, the measured (noisy) run the model was identified from, as a
// run log (firmware/runlog/README.md). In the loop the gateway's log is already there.
std::vector<std::string> write_runs(const CampaignResult& result, const fs::path& dir,
                                    bool in_the_loop) {
  const auto plant = sim::make_plant(result.plant);
  std::vector<std::string> written;
  for (const Experiment& e : result.experiments) {
    const std::string relative = "runs/" + experiment_folder(e.number, e.name) + "/run.csv";
    if (!in_the_loop) {
      fs::create_directories((dir / relative).parent_path());
      SimulatedRun run;
      run.plant = result.plant;
      run.plan = e.name;
      run.producer = "excite campaign " + std::string(runlog::kVersion);
      run.sample_time_min = e.sample_time_min;
      run.input_names = result.input_names;
      run.output_names = result.output_names;
      run.input_units = result.input_units;
      run.output_units = result.output_units;
      run.input_baseline = plant->input_baseline();
      run.du = e.U;
      run.dy = e.Y;
      write_run_log(run, dir / relative);
    }
    written.push_back(fs::exists(dir / relative) ? relative : std::string());
  }
  return written;
}

// The closed-loop campaign: its designs run under the controller, identified two-stage.
void run_closed_loop(const CampaignCommandOptions& opt,
                     const std::function<void(const std::string&)>& say) {
  ClosedLoopCampaignOptions c;
  c.plant = opt.campaign.plant;
  c.controller = opt.controller;
  c.design.excitation = opt.excitation;
  c.designs = opt.designs;
  c.design.limit_fraction = opt.limit_fraction;
  c.design.mv_fraction = opt.mv_fraction;
  c.design.directions = opt.directions;
  c.design.switching = opt.switching;
  if (!opt.limits.empty()) {
    const CvLimits limits =
        parse_cv_limits(opt.limits, sim::make_plant(c.plant)->output_names(), "the plant's");
    c.design.cv_low = limits.low;
    c.design.cv_high = limits.high;
    if (!c.design.cv_low.allFinite() || !c.design.cv_high.allFinite()) {
      throw std::invalid_argument(
          "--limit = (not every CV), expected a test limit for every "
          "CV of " +
          c.plant);
    }
  }
  c.noise_variance = opt.campaign.noise_variance;
  c.seed = opt.campaign.seed;
  c.threads = opt.campaign.threads;
  c.loop = opt.loop;
  WholeFolder folder(opt.output_dir, opt.overwrite, "campaign");
  const fs::path& out = folder.staging();
  if (opt.loop) {
    c.programs = programs_beside_this_one();
    say("every closed-loop design goes through the real excite-gateway to excite-plant "
        "--controller (Modbus TCP on 127.0.0.1, lock-step); runs in " +
        (out / "runs").string());
  }
  const ClosedLoopCampaign campaign = run_closed_loop_campaign(c, out, say);
  const std::vector<ClosedLoopExperiment>& runs = campaign.runs;
  const ClosedLoopCampaignHeader header{.plant = c.plant,
                                        .controller = c.controller,
                                        .excitation = c.design.excitation,
                                        .directions = c.design.directions,
                                        .switching = c.design.switching,
                                        .tau_low_min = campaign.tau_low_min,
                                        .loop_speed = campaign.loop_speed,
                                        .loop = c.loop,
                                        .open_loop_report = opt.open_loop_report,
                                        .threads = c.threads};
  write_closed_loop_summary(header, runs, out);
  write_closed_loop_report(header, runs, out);
  folder.commit();
  const fs::path done(opt.output_dir);
  std::cout << "wrote " << (done / "index.html").string() << " (closed-loop report), "
            << (done / "summary.json").string() << ", " << runs.size() << " models in "
            << (done / "models").string() << "/\n";
}

void run(CampaignCommandOptions opt) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::mutex say_mutex;
  const auto say = [&](const std::string& line) {
    const std::lock_guard<std::mutex> lock(say_mutex);
    std::cerr << "[" << static_cast<int>(elapsed() * 10) / 10.0 << " s] " << line << std::endl;
  };
  if (!opt.controller.empty()) {
    run_closed_loop(opt, say);
    return;
  }
  if (!opt.limits.empty() || !opt.designs.empty() || !opt.open_loop_report.empty() ||
      opt.directions != "none" || opt.switching != "loop") {
    throw std::invalid_argument(
        "--limit/--designs/--directions/--switching/--open-loop-report without --controller, "
        "expected --controller FILE (they choose the closed-loop "
        "designs)");
  }
  if (opt.structure != "auto") opt.campaign.structure = structure_from_string(opt.structure);
  WholeFolder folder(opt.output_dir, opt.overwrite, "campaign");
  const fs::path& out = folder.staging();
  if (opt.loop) {
    opt.campaign.measured_run = measured_runs_in_the_loop(opt.campaign.plant, out / "runs",
                                                          programs_beside_this_one(), say);
    say("every plan goes through the real excite-gateway to excite-plant (Modbus TCP on "
        "127.0.0.1, lock-step); runs in " +
        (out / "runs").string());
  }
  const CampaignResult result = run_campaign(opt.campaign, say);
  write_summary(result, out);
  ReportArtifacts artifacts;
  artifacts.models = write_models(result, out);
  artifacts.run_logs = write_runs(result, out, opt.loop);
  const double before_report = elapsed();
  write_report(result, *sim::make_plant(opt.campaign.plant), out, artifacts, opt.campaign.threads);
  say("report and figures in " + std::to_string(elapsed() - before_report) + " s");
  folder.commit();
  const fs::path done(opt.output_dir);
  std::cout << "wrote " << (done / "index.html").string() << " (report), "
            << (done / "summary.json").string() << ", " << (done / "models").string()
            << "/ and run logs in " << (done / "runs").string() << "/ in " << elapsed() << " s\n";
}

}  // namespace

void add_campaign_command(CLI::App& app) {
  auto opt = std::make_shared<CampaignCommandOptions>();
  CLI::App* cmd = app.add_subcommand("campaign",
                                     "Design the 17 standard experiments for a plant, run, "
                                     "identify and cross-validate them, and write an HTML report");
  cmd->add_option("--plant", opt->campaign.plant, "plant with a case study")->required();
  cmd->add_option("-o,--output-dir", opt->output_dir,
                  "folder for summary.json, index.html, figures/")
      ->required();
  const std::map<std::string, DesignGain> gains = {{"true", DesignGain::true_gain},
                                                   {"step-test", DesignGain::step_test}};
  cmd->add_option("--design-gain", opt->campaign.design_gain,
                  "G(0) the designs use: true (default, the plant's) or step-test (its estimate)")
      ->transform(CLI::CheckedTransformer(gains, CLI::ignore_case));
  cmd->add_option("--noise-var", opt->campaign.noise_variance,
                  "measurement noise variance per output (default: the case study's)")
      ->check(finite_non_negative());
  cmd->add_option("--seed", opt->campaign.seed, "noise seed")->capture_default_str();
  opt->campaign.threads = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  cmd->add_option("--threads", opt->campaign.threads,
                  "experiments identified and cross-validated in parallel (default: the cores)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_flag("--loop", opt->loop,
                "stream every plan through the real excite-gateway to excite-plant (Modbus TCP "
                "on 127.0.0.1, lock-step) instead of simulating it in this process");
  cmd->add_flag("--allow-unequal-length", opt->campaign.allow_unequal_length,
                "compare designs of different lengths (refused by default, naming every "
                "length: SPEC §4 judges every design on equally long data)");
  std::vector<std::string> structures{"auto"};
  for (int k = 0; k < kStructures; ++k)
    structures.emplace_back(to_string(static_cast<Structure>(k)));
  cmd->add_option("--structure", opt->structure,
                  "every element of every model in this structure, as excite identify "
                  "--structure: auto (chosen per element by BIC) or one for all; two_poles is "
                  "the thesis's model class (two poles and a delay, 6.1.1)")
      ->capture_default_str()
      ->check(CLI::IsMember(structures));
  cmd->add_flag("--overwrite", opt->overwrite,
                "replace DIR whole even when it holds files that are not a previous campaign's");
  cmd->add_option("--controller", opt->controller,
                  "with the controller on (issue 42): the closed-loop designs, each run under "
                  "this controller file (sim/control/README.md) and identified two-stage; with "
                  "--loop through the real gateway to excite-plant --controller")
      ->check(CLI::ExistingFile);
  cmd->add_option("--excitation", opt->excitation,
                  "with --controller: r on the CV setpoints (setpoint) or an MV dither (mv)")
      ->capture_default_str()
      ->check(CLI::IsMember({"setpoint", "mv"}));
  cmd->add_option("--limit", opt->limits,
                  "with --controller, setpoint: CV test limits CV=LOW:HIGH (deviations), every "
                  "CV (default: the DMC controller file's [[cv]] limits)");
  cmd->add_option("--limit-fraction", opt->limit_fraction,
                  "with --controller, setpoint: the amplitude's share of each CV's test limit")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--mv-fraction", opt->mv_fraction,
                  "with --controller, setpoint: r scaled down until its steady-state MV moves "
                  "stay within this share of each MV's limits (the controller file's [[mv]]); "
                  "0: sized by the CV limits alone")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--directions", opt->directions,
                  "with --controller, setpoint: none (each CV its own signal) or output (the "
                  "same signals along the prior's output directions W of G(0) = W Sigma V')")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "output"}));
  cmd->add_option("--switching", opt->switching,
                  "with --controller, setpoint: the designs' (4.2.3) tau_L from the loop's speed "
                  "along the prior's weakest output direction (loop) or the plant's, as open "
                  "loop (plant)")
      ->capture_default_str()
      ->check(CLI::IsMember({"loop", "plant"}));
  cmd->add_option("--designs", opt->designs,
                  "with --controller: the plain presets to run (default: every one)")
      ->delimiter(',');
  cmd->add_option("--open-loop-report", opt->open_loop_report,
                  "with --controller: a link from the closed-loop report to the open-loop one "
                  "(a path relative to DIR)");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
