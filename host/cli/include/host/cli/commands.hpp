// SPDX-License-Identifier: MIT
#pragma once
// The subcommands of `excite`. Each registers its options on the app and runs when chosen;
// errors are thrown and turned into one message and a non-zero exit by main().

#include <CLI/CLI.hpp>

namespace excite::host::cli {

void add_gains_command(CLI::App& app);
void add_design_command(CLI::App& app);
void add_inspect_command(CLI::App& app);
void add_case_study_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_identify_command(CLI::App& app);
void add_import_command(CLI::App& app);     // historian CSV -> run log
void add_validate_commands(CLI::App& app);  // validate, crossval
void add_balance_command(CLI::App& app);
void add_campaign_command(CLI::App& app);
void add_loop_config_command(CLI::App& app);
void add_montecarlo_command(CLI::App& app);  // montecarlo, montecarlo merge
void add_scale_command(CLI::App& app);       // predictive amplitude control (issue 26 §2)
void add_test_command(CLI::App& app);        // the adaptive plant test (issue 26 §3)
void add_export_command(
    CLI::App& app);  // export MODEL --format …  // loop-config (excite-plant + gateway pair)

}  // namespace excite::host::cli
