// SPDX-License-Identifier: MIT
// excite montecarlo --plant P [--designs a,b,…] --seeds N [--first-seed S] [--threads T]
//                   [--noise-var V] [--length-step PCT] [--warm-grid] [--perturb X]
//                   [--shard i/N] -o DIR
//   with the controller on: --controller FILE [--excitation setpoint|mv] [--method M]
//                   [--limit-fraction F] [--mv-fraction F] [--directions none|output]
//                   [--switching loop|plant] [--prbs-phase K] [--controller-perturb X]
//                   [--disturbance-std S --disturbance-tau-min T]
// excite montecarlo … --emit-slurm FILE [--slurm-tasks N] -o OUT   (a Slurm job array script)
// excite montecarlo merge DIR… -o OUT
// The campaign's experiment over noise seeds (host/montecarlo): every finished (design, seed)
// unit is kept in DIR, so a run stopped by Ctrl-C (SIGINT) or SIGTERM resumes when the same
// command is run again. A whole run (no --shard, or 1/1) ends with DIR/summary.json, the
// table on stdout and the report DIR/index.html; a shard ends with its units, and `merge`
// makes OUT/summary.json and OUT/index.html from all shards. Progress goes to stderr: a
// live line on a terminal, plain lines (at most one a second, and the last) otherwise. Exit
// status 130 when interrupted.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/case_studies.hpp"
#include "host/montecarlo/merge.hpp"
#include "host/montecarlo/report.hpp"
#include "host/montecarlo/run.hpp"
#include "host/montecarlo/slurm.hpp"
#include "host/montecarlo/summary.hpp"
#include "host/output/own_entries.hpp"
#include "host/output/whole_file.hpp"
#include "sim/library/perturb.hpp"

namespace excite::host::cli {
namespace {

namespace fs = std::filesystem;
namespace mc = excite::host::montecarlo;
using mc::UnitTimes;

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler stores it");

extern "C" void on_stop_signal(int) {
  g_stop.store(true);
}

// SIGINT and SIGTERM set the stop flag once; a second one (SA_RESETHAND) ends the process.
void catch_stop_signals() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = static_cast<int>(SA_RESETHAND);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

std::string clock_text(double seconds) {
  const auto s = static_cast<long long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
  }
  return text;
}

// Progress on stderr: a bar redrawn in place on a terminal, else plain lines.
class ProgressPrinter {
 public:
  ProgressPrinter() : terminal_(::isatty(STDERR_FILENO) == 1) {}
  void operator()(const mc::Progress& p) {
    const bool last = p.done == p.total;
    if (!terminal_ && !last && p.last != nullptr && p.elapsed_s - printed_at_ < 1.0) return;
    printed_at_ = p.elapsed_s;
    std::string line =
        "montecarlo: " + std::to_string(p.done) + "/" + std::to_string(p.total) + " units";
    if (p.done_before > 0) line += " (" + std::to_string(p.done_before) + " from before)";
    line += ", " + clock_text(p.elapsed_s) + " elapsed";
    line += p.left_s >= 0.0 ? ", about " + clock_text(p.left_s) + " left" : ", time left unknown";
    if (terminal_) {
      constexpr int width = 24;
      const int filled = p.total > 0 ? width * p.done / p.total : width;
      std::cerr << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
                << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << line
                << "   " << (last ? "\n" : "") << std::flush;
    } else {
      std::cerr << line << std::endl;
    }
  }
  void end_line() const {
    if (terminal_) std::cerr << "\n";
  }

 private:
  bool terminal_;
  double printed_at_ = -1e9;
};

// summary.json, the table on stdout, and the report (index.html with its figures), written
// into `dir`, named as in `shown` (where they will be).
void write_summary(const mc::Config& config, const std::vector<mc::UnitResult>& units,
                   const fs::path& dir, const fs::path& shown, int threads) {
  const nlohmann::json summary = mc::summary_json(config, units);
  write_whole_file(dir / "summary.json", summary.dump(2) + "\n");
  std::cout << mc::summary_text(summary) << "wrote " << (shown / "summary.json").string() << "\n";
  mc::write_report(summary, units, dir, threads);
  std::cout << "wrote " << (shown / "index.html").string() << " (the report)\n";
}

struct Options {
  mc::Config config;
  std::string shard = "1/1";
  std::string perturb = "0";
  std::string controller_perturb = "0";
  std::string output_dir;
  int threads = 1;
  std::vector<std::string> merge_dirs;
  std::string merge_output;
  bool merge_overwrite = false;
  std::string emit_slurm;  // script file; empty: run here
  int slurm_tasks = 10;
};

// "--controller-perturb = TEXT" as sim::parse_perturb reads "--perturb", named as itself.
double parse_controller_perturb(const std::string& text) {
  try {
    return sim::parse_perturb(text);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("--controller-perturb = " + text +
                                ", expected a number of percent, 0 <= X < 100");
  }
}

// Writes the Slurm submission script instead of running (host/montecarlo/slurm.hpp).
void emit_slurm(const Options& opt) {
  if (opt.shard != "1/1")
    throw std::invalid_argument("--shard = " + opt.shard +
                                ", expected none with --emit-slurm (--slurm-tasks cuts the run)");
  mc::SlurmJob job;
  job.excite = fs::read_symlink("/proc/self/exe");
  job.output_dir = fs::absolute(opt.output_dir).lexically_normal();
  job.tasks = opt.slurm_tasks;
  job.threads = opt.threads;
  write_whole_file(opt.emit_slurm, mc::slurm_script(opt.config, job));
  std::cout << "wrote " << opt.emit_slurm << ": " << opt.slurm_tasks
            << " array tasks and a merge job into " << job.output_dir.string()
            << "; submit with: sh " << opt.emit_slurm << "\n";
}

void run(Options opt) {
  opt.config.shard = mc::parse_shard(opt.shard);
  opt.config.perturb_percent = sim::parse_perturb(opt.perturb);
  mc::ClosedLoopConfig& loop = opt.config.closed_loop;
  if (loop.on()) {
    loop.controller = fs::absolute(loop.controller).lexically_normal().string();
    loop.model_perturb_percent = parse_controller_perturb(opt.controller_perturb);
  }
  if (opt.config.noise_variance < 0.0)
    opt.config.noise_variance = case_study_noise_variance(opt.config.plant);
  case_study(opt.config.plant);  // an unknown plant or one without a case study: its message
  mc::normalise(opt.config);
  if (!opt.emit_slurm.empty()) {
    emit_slurm(opt);
    return;
  }
  catch_stop_signals();
  ProgressPrinter printer;
  const mc::Outcome outcome = mc::run_into(
      opt.config, opt.output_dir, opt.threads, [&](const mc::Progress& p) { printer(p); }, g_stop);
  for (const std::string& why : outcome.redone)
    std::cerr << "montecarlo: run again, its file does not read back: " << why << std::endl;
  const int ran = outcome.done - outcome.done_before;
  if (ran > 0) {
    const UnitTimes& t = outcome.unit_cpu;
    const double cpu = outcome.design_cpu_s + t.experiment_s + t.crossval_s + t.lengths_s;
    char line[400];
    std::snprintf(line, sizeof line,
                  "montecarlo: %d units in %.1f s wall, %.1f CPU s: designs %.1f, experiments "
                  "(simulate, identify, balance) %.1f, cross-validation %.1f, test lengths %.1f; "
                  "%.3f units per CPU second (%.3f without the test lengths)",
                  ran, outcome.wall_s, cpu, outcome.design_cpu_s, t.experiment_s, t.crossval_s,
                  t.lengths_s, ran / cpu, ran / (cpu - t.lengths_s));
    std::cerr << line << std::endl;
  }
  if (!outcome.complete) {
    printer.end_line();
    std::cerr << "montecarlo: interrupted: " << outcome.done << " of " << outcome.total
              << " units kept in " << opt.output_dir << "; run the same command again to resume"
              << std::endl;
    std::exit(130);
  }
  if (opt.config.shard.count == 1) {
    write_summary(opt.config, mc::read_units(opt.config, opt.output_dir), opt.output_dir,
                  opt.output_dir, std::min(opt.threads, 2));
  } else {
    std::cout << "shard " << opt.shard << " complete: " << outcome.total << " units in "
              << opt.output_dir << "; merge all " << opt.config.shard.count
              << " shards with: excite montecarlo merge DIR… -o OUT\n";
  }
}

void merge(const Options& opt) {
  std::vector<fs::path> dirs(opt.merge_dirs.begin(), opt.merge_dirs.end());
  // OUT's own names only: the shards and Slurm's logs may live in OUT
  // (host/output/own_entries.hpp).
  OwnEntries out(opt.merge_output, opt.merge_overwrite, "montecarlo merge",
                 {"summary.json", "index.html", "figures"});
  const mc::Merged merged = mc::merge_shards(dirs);
  write_summary(merged.config, merged.units, out.staging(), opt.merge_output, 2);
  out.commit();
}

// The options of a run with the controller on (issue 41 §4), each only with --controller.
void add_closed_loop_options(CLI::App& cmd, Options& opt) {
  mc::ClosedLoopConfig& loop = opt.config.closed_loop;
  CLI::Option* controller =
      cmd.add_option("--controller", loop.controller,
                     "with the controller on (issue 41): the closed-loop designs (plain presets), "
                     "each unit run in process under this controller file (sim/control/README.md) "
                     "and identified (--method), its test-length prefixes too");
  cmd.add_option("--excitation", loop.excitation,
                 "with --controller: r on the CV setpoints (setpoint) or an MV dither (mv)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option(
         "--method", loop.method,
         "with --controller: the estimate judged, two-stage (the projection on r) or "
         "direct (the prediction-error fit with an AR or ARMA(1,1) noise model on the applied u: "
         "consistent under feedback when the noise model describes the disturbance)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--limit-fraction", loop.limit_fraction,
                 "with --controller, setpoint: each CV's amplitude, share of its test limit "
                 "(the controller file's [[cv]] limits)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--mv-fraction", loop.mv_fraction,
                 "with --controller, setpoint: r scaled down until its steady-state MV moves "
                 "stay within this share of each MV's limits (0: off)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--directions", loop.directions,
                 "with --controller, setpoint: none (each CV its own signal) or output (the same "
                 "signals along the prior's output directions, r = c W s; under integral action "
                 "the MVs' room goes to the weak input directions)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--switching", loop.switching,
                 "with --controller, setpoint: the designs' (4.2.3) tau_L from the loop's speed "
                 "along the prior's weakest output direction (loop) or the plant's, as open loop "
                 "(plant)")
      ->capture_default_str()
      ->check(CLI::IsMember({"loop", "plant"}))
      ->needs(controller);
  cmd.add_option("--prbs-phase", loop.prbs_phase,
                 "with --controller, setpoint: every design's PRBS started K switching intervals "
                 "in: another realisation of r (every seed gets the same r)")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{0}, mc::kMaxPrbsPhase))
      ->needs(controller);
  cmd.add_option("--controller-perturb", opt.controller_perturb,
                 "with --controller: the controller's model perturbed per seed, every gain, "
                 "time constant and delay within +-X % (percent, 0 <= X < 100)")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--disturbance-std", loop.disturbance_std,
                 "with --controller: the coloured output disturbance's standard deviation")
      ->capture_default_str()
      ->needs(controller);
  cmd.add_option("--disturbance-tau-min", loop.disturbance_tau_min,
                 "with --controller: the disturbance's time constant, minutes")
      ->capture_default_str()
      ->needs(controller);
}

}  // namespace

void add_montecarlo_command(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  opt->config.noise_variance = -1.0;
  CLI::App* cmd = app.add_subcommand(
      "montecarlo",
      "The campaign's experiments over noise seeds: spread of fit, cross-fit, balance and "
      "σ_i per design, the share of seeds meeting the accuracy criterion, and T90");
  cmd->add_option("--plant", opt->config.plant, "plant with a case study");
  cmd->add_option("--designs", opt->config.designs,
                  "Table 6.1 acronyms, comma-separated (default: all 17)")
      ->delimiter(',');
  cmd->add_option("--seeds", opt->config.seeds, "number of noise seeds (1 to 1000000)");
  cmd->add_option("--first-seed", opt->config.first_seed, "the first seed")->capture_default_str();
  opt->threads = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  cmd->add_option("--threads", opt->threads, "units run in parallel (default: the cores)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--noise-var", opt->config.noise_variance,
                  "measurement noise variance per output (default: the case study's)")
      ->check(finite_non_negative());
  cmd->add_option("--length-step", opt->config.length_step_percent,
                  "test-length grid step in percent of the run (0: the whole run only)")
      ->capture_default_str();
  cmd->add_flag_callback(
      "--warm-grid", [opt] { opt->config.length_grid_start = mc::GridStart::warm; },
      "fit each prefix of the length grid from the previous length's model too, checked against "
      "the cold fit until it settles (about 1.3x cheaper; a few verdicts differ, mostly to the "
      "better fit: host/montecarlo/README.md)");
  cmd->add_option("--perturb", opt->perturb,
                  "perturbed true plant: every gain, time constant and delay within +-X % per "
                  "seed; the designs keep the nominal plant (percent, 0 <= X < 100)")
      ->capture_default_str();
  add_closed_loop_options(*cmd, *opt);
  cmd->add_option("--shard", opt->shard, "run shard i of N of the (design × seed) units")
      ->capture_default_str();
  cmd->add_option("-o,--output-dir", opt->output_dir,
                  "folder for run.json, units/ and summary.json (kept between runs: resume)");
  cmd->add_option("--emit-slurm", opt->emit_slurm,
                  "write a Slurm submission script (job array + merge job) to this file instead "
                  "of running; -o DIR is where the nodes write");
  cmd->add_option("--slurm-tasks", opt->slurm_tasks, "array tasks (shards) of --emit-slurm")
      ->capture_default_str();
  CLI::App* merge_cmd = cmd->add_subcommand(
      "merge", "Combine the folders of all shards of a run into OUT/summary.json");
  merge_cmd->add_option("dirs", opt->merge_dirs, "the shards' folders")->required();
  merge_cmd
      ->add_option("-o,--output-dir", opt->merge_output,
                   "folder for summary.json, index.html, figures/ (new, or a previous "
                   "merge's; anything else in it is kept)")
      ->required();
  merge_cmd->add_flag("--overwrite", opt->merge_overwrite,
                      "replace OUT's summary.json, index.html and figures/ even when excite did "
                      "not write them");
  merge_cmd->callback([opt] { merge(*opt); });
  cmd->callback([opt, merge_cmd, cmd] {
    if (merge_cmd->parsed()) return;
    for (const char* name : {"--plant", "--seeds", "--output-dir"}) {
      if (cmd->get_option(name)->count() == 0)
        throw CLI::RequiredError(std::string(name) + " is required (or: montecarlo merge)");
    }
    run(*opt);
  });
}

}  // namespace excite::host::cli
