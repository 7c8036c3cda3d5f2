// SPDX-License-Identifier: MIT
#pragma once
// The controller file (TOML, read through base/config: strict keys, typed and ranged
// getters, errors "FILE:LINE:COL: FIELD = VALUE, expected WHAT"), and its writer beside the
// reader: what controller_file_toml writes, controller_from_toml reads back unchanged.
// Format and examples: sim/control/README.md ("The controller file").
//
//   kind = "dmc" | "pi"         sample_time_min = T
//   [model]  plant = NAME or FILE.toml | model_file = MODEL.json; probe_step; delay_samples
//   [dmc]    prediction_horizon, control_horizon, slack_weight, max_qp_iterations
//   [[mv]]   min, max, max_move, move_suppression (dmc)     one per MV, in the model's order
//   [[cv]]   weight, zone = [lo, hi], limits = [lo, hi]    (dmc) one per CV
//   [[pairing]]  cv, mv (1-based), kc, ti_min               (pi)
//
// What needs the model (the counts of [[mv]] and [[cv]], the pairings' ranges, integral
// controllability) is checked when the controller is made (make_controller.hpp).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sim/control/dmc.hpp"
#include "sim/control/pi.hpp"

namespace excite::sim::control {

enum class ControllerKind { dmc, pi };

/// Where the controller's model comes from. Exactly one of `plant` (a library plant's name
/// or a plant file, sim/lti) and `model_file` (a model of `excite identify`, JSON: read by
/// excite, host/export's plant_from_model, since sim does not read host's formats).
struct ModelSource {
  std::string plant;
  std::string model_file;
  double probe_step = 1.0;  // MV step of the step-response probes (step_model.hpp)
  int delay_samples = 0;    // the loop's own delay from reading y to applying u, samples
};

struct ControllerFile {
  std::string source;  // the file's name in messages
  ControllerKind kind = ControllerKind::dmc;
  double sample_time_min = 1.0;
  ModelSource model;
  DmcSettings dmc;              // dmc: horizons and weights; both kinds: dmc.mv (MV limits)
  bool mv_given = false;        // [[mv]] present (else one default entry per model MV)
  bool cv_given = false;        // [[cv]] present (dmc)
  std::vector<PiLoop> pairing;  // pi; cv and mv 0-based here, 1-based in the file
};

/// Reads a controller file's text; `source` names it in messages. Throws config::Error.
ControllerFile controller_from_toml(std::string_view text, std::string_view source);
/// Reads a controller file; a relative `model.plant` path is taken relative to its folder.
ControllerFile load_controller_file(const std::filesystem::path& path);

/// The file's TOML text (base/config/writer.hpp's value forms): controller_from_toml reads
/// it back to the same ControllerFile (source aside).
std::string controller_file_toml(const ControllerFile& file);

}  // namespace excite::sim::control
