// SPDX-License-Identifier: MIT
// excite: the engineer's tool. Exit codes: 0 success, 1 an error (message on stderr),
// 2 a usage error (CLI11's message on stderr).

#include <cstdio>
#include <exception>
#include <string>

#include "firmware/runlog/format.hpp"

#include "host/cli/commands.hpp"
#include "host/cli/error_text.hpp"
#include "host/cli/short_numbers.hpp"

int main(int argc, char** argv) {
  CLI::App app{"excite: input design and identification for ill-conditioned multivariable plants"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "excite " + std::string(excite::runlog::kVersion));
  excite::host::cli::add_gains_command(app);
  excite::host::cli::add_design_command(app);
  excite::host::cli::add_inspect_command(app);
  excite::host::cli::add_case_study_command(app);
  excite::host::cli::add_simulate_command(app);
  excite::host::cli::add_import_command(app);
  excite::host::cli::add_identify_command(app);
  excite::host::cli::add_validate_commands(app);
  excite::host::cli::add_balance_command(app);
  excite::host::cli::add_campaign_command(app);
  excite::host::cli::add_loop_config_command(app);
  excite::host::cli::add_montecarlo_command(app);
  excite::host::cli::add_export_command(app);
  excite::host::cli::add_scale_command(app);
  excite::host::cli::add_test_command(app);
  app.failure_message([](const CLI::App* a, const CLI::Error& e) {
    return excite::host::cli::printable(
        excite::host::cli::short_numbers(CLI::FailureMessage::simple(a, e)));
  });
  // "-hist.csv" is not -h: CLI11 would read it as -h -i -s … and print the help, exit 0.
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--") break;
    if (arg.size() > 2 && arg[0] == '-' && arg[1] == 'h') {
      std::fprintf(stderr,
                   "excite: error: option = %s, expected a known option (-h alone asks for "
                   "help; a file name that starts with '-' goes after --, or as ./%s)\n",
                   excite::host::cli::printable(arg).c_str(),
                   excite::host::cli::printable(arg).c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --version: 0
  } catch (const std::exception& e) {
    std::fprintf(stderr, "excite: error: %s\n",
                 excite::host::cli::printable(
                     excite::host::cli::short_numbers(excite::host::cli::error_text(e)))
                     .c_str());
    return 1;
  }
  return 0;
}
