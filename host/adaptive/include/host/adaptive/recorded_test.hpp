// SPDX-License-Identifier: MIT
#pragma once
// An adaptive test with its record, as `excite test` runs it (host/README.md, host/adaptive/
// README.md): the options checked before the folder is made, then the loop of
// adaptive_test.hpp with a FolderLog (test_folder.hpp), then what is left when it stops.
//   - on a simulated plant in process: DIR/decisions.jsonl, status.txt, segments/, the whole
//     test as one run log DIR/run.csv and the last model DIR/model.json;
//   - through a running excite-gateway (its segment inbox and its growing run log,
//     inbox_runner.hpp): the same without run.csv (the gateway's log is the record);
//   - a study over seeds judged against the truth (study.hpp): DIR/study.json, and under CV
//     limits how the fixed designs fare on the same plants.
// What the operator must do and what was written goes to `out` (the terminal). Errors are
// std::invalid_argument (options) or std::runtime_error (files, the gateway).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/adaptive/adaptive_test.hpp"
#include "host/adaptive/study.hpp"
#include "host/design/prior_knowledge.hpp"

namespace excite::host {

/// One test on a library plant (or plant file) in process, its case study the prior.
struct SimulatedTest {
  std::string plant;
  std::filesystem::path folder;
  std::uint64_t seed = 1;
  double noise_variance = -1.0;     // < 0: the case study's
  double perturb_percent = 0.0;     // > 0: the true plant perturbed for `seed` (linear plants)
  std::vector<std::string> limits;  // --limit CV=LOW:HIGH texts (cv_limit_text.hpp)
  AdaptiveOptions adaptive;
};
void run_simulated_test(const SimulatedTest& test, std::ostream& out);

/// One test through a running gateway; its outputs are named y1, y2, … by the prior's rows.
struct GatewayTest {
  PriorKnowledge prior;
  std::filesystem::path folder;
  std::string inbox, run_log;        // the gateway's --segment-inbox and --log
  double segment_timeout_min = 0.0;  // 0: the plain design's length
  std::vector<std::string> limits;
  AdaptiveOptions adaptive;
};
void run_gateway_test(const GatewayTest& test, std::ostream& out);

/// A study over seeds (study.hpp) written to `folder`/study.json.
struct RecordedStudy {
  std::string plant;
  std::filesystem::path folder;
  std::uint64_t first_seed = 1;
  int seeds = 1;
  int threads = 1;
  double noise_variance = -1.0;
  double perturb_percent = 0.0;
  std::vector<std::string> limits;
  AdaptiveOptions adaptive;
  std::optional<ClosedLoopStudyOptions> closed_loop;  // the controller on; no limits given:
                                                      // the controller file's CV limits
};
void run_recorded_study(const RecordedStudy& study, std::ostream& out);

}  // namespace excite::host
