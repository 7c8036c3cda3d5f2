// SPDX-License-Identifier: MIT
#pragma once
// The model file `excite identify -o MODEL` writes and `excite validate` reads: the
// identified model as JSON (host/README.md). It is also what --json prints.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "host/export/formats.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/identify/identify.hpp"

namespace excite::host {

/// {"format":"excite model v2","sample_time_min","inputs":[names],"outputs":[{"name","fit",
///  "elements":[{"input","structure","K","Td","Tp1","Tp2","Tz","Tn","zeta","se":{…},
///  "covariance":[[…]…],"K_interval95":[lower, upper],"K_projected":{"lower","upper","why"},
///  "status","reason","grade",…}…],"gain_covariance"}…],
///  "gain","singular_values","condition_number","xi","rga",…}; null for what is unknown.
/// Every parameter is written (those outside the element's structure at their neutral values,
/// element.hpp); "se" and "covariance" cover the structure's parameters, in Parameter order.
/// "K_interval95" is the reported 95 % interval of K (gain_interval_95, derived on writing);
/// "K_projected" the projection it holds, only where there is one (read back).
/// v1 files (no structure: two_poles) still read.
nlohmann::json model_json(const IdentificationResult& result,
                          const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names);

/// The model file's `closed_loop` block for a model identified from a closed-loop run (issue 41
/// §3): {"method": the model written ("two-stage" or "direct"), "excitation", "controller",
/// "stage1": {"laguerre_functions" per r channel, "laguerre_pole" (0: a FIR of as many
/// lags), "u_explained_by_r_percent": per input, "two_stage_se_factor" and "iv_gain_step":
/// per output, per input (ClosedLoopIdentification::stage1_se_factor, iv_gain_step)}, the
/// other method's
/// {"gain", "gain_std_error"} under its name ("direct" or "two_stage"), the cross-check, and
/// "feedback_bias_suspected": [{"element", "two_stage", "direct", "sigma"}…]}. One writer for
/// `excite identify` and the closed-loop campaign.
nlohmann::json closed_loop_json(const ClosedLoopIdentification& id, const runlog::RunLog& log,
                                bool direct_written);

/// At most this many inputs and this many outputs in a model file, checked before anything
/// is allocated for them (the identified elements are inputs × outputs).
inline constexpr std::size_t kMaxModelChannels = 64;

/// A model's channel names, in its order.
struct ModelChannels {
  std::vector<std::string> inputs, outputs;
};

/// Reads a model file (and its channel names into `channels` when given). Throws
/// std::invalid_argument "<path>: <field>: <what was expected>".
IdentifiedModel read_model_file(const std::filesystem::path& path,
                                ModelChannels* channels = nullptr);

/// The model's channels must be the run's, same names in the same order; otherwise
/// std::invalid_argument naming both files and both lists.
void check_same_channels(const ModelChannels& model, const std::string& model_path,
                         const std::vector<std::string>& run_inputs,
                         const std::vector<std::string>& run_outputs, const std::string& run_path);

/// The same with the names of the inputs and outputs (`source` is the path).
NamedModel read_named_model_file(const std::filesystem::path& path);

}  // namespace excite::host
