// SPDX-License-Identifier: MIT
// excite campaign --plant NAME -o DIR [--design-gain true|step-test] [--noise-var V] [--seed S]
//                 [--threads N]
// The chapter-6 study: DIR/summary.json and the report DIR/index.html.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <thread>

#include "host/campaign/campaign.hpp"
#include "host/campaign/report.hpp"
#include "host/cli/commands.hpp"

namespace excite::host::cli {
namespace {

struct CampaignCommandOptions {
  CampaignOptions campaign;
  std::string output_dir;
};

void run(const CampaignCommandOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const CampaignResult result = run_campaign(opt.campaign, [&](const std::string& line) {
    std::cerr << "[" << static_cast<int>(elapsed() * 10) / 10.0 << " s] " << line << std::endl;
  });
  std::filesystem::create_directories(opt.output_dir);
  write_summary(result, opt.output_dir);
  write_report(result, *sim::make_plant(opt.campaign.plant), opt.output_dir);
  std::cout << "wrote " << opt.output_dir << "/summary.json and " << opt.output_dir
            << "/index.html in " << elapsed() << " s\n";
}

}  // namespace

void add_campaign_command(CLI::App& app) {
  auto opt = std::make_shared<CampaignCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "campaign",
      "The chapter-6 study on a plant: 17 designs, identified, cross-validated, reported");
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
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", opt->campaign.seed, "noise seed")->capture_default_str();
  opt->campaign.threads = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  cmd->add_option("--threads", opt->campaign.threads,
                  "experiments identified and cross-validated in parallel (default: the cores)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
