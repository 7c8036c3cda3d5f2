// SPDX-License-Identifier: MIT
// The controller file's writer, beside its reader (controller_file.cpp): every value in
// base/config/writer.hpp's forms, so the reader reads back what is written.
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "base/config/writer.hpp"
#include "sim/control/controller_file.hpp"

namespace excite::sim::control {

std::string controller_file_toml(const ControllerFile& file) {
  using config::toml_number;
  using config::toml_string;
  std::ostringstream out;
  const bool dmc = file.kind == ControllerKind::dmc;
  out << "kind = " << (dmc ? "\"dmc\"" : "\"pi\"") << "\n";
  out << "sample_time_min = " << toml_number(file.sample_time_min) << "\n\n";
  out << "[model]\n";
  if (!file.model.plant.empty()) out << "plant = " << toml_string(file.model.plant) << "\n";
  if (!file.model.model_file.empty()) {
    out << "model_file = " << toml_string(file.model.model_file) << "\n";
  }
  out << "probe_step = " << toml_number(file.model.probe_step) << "\n";
  out << "delay_samples = " << file.model.delay_samples << "\n";
  if (dmc) {
    out << "\n[dmc]\n";
    out << "prediction_horizon = " << file.dmc.prediction_horizon << "\n";
    out << "control_horizon = " << file.dmc.control_horizon << "\n";
    out << "slack_weight = " << toml_number(file.dmc.slack_weight) << "\n";
    out << "max_qp_iterations = " << file.dmc.max_qp_iterations << "\n";
  }
  for (const MvSettings& m : file.dmc.mv) {
    out << "\n[[mv]]\n";
    if (std::isfinite(m.min)) out << "min = " << toml_number(m.min) << "\n";
    if (std::isfinite(m.max)) out << "max = " << toml_number(m.max) << "\n";
    if (std::isfinite(m.max_move)) out << "max_move = " << toml_number(m.max_move) << "\n";
    if (dmc) out << "move_suppression = " << toml_number(m.move_suppression) << "\n";
  }
  if (dmc) {
    for (const CvSettings& c : file.dmc.cv) {
      out << "\n[[cv]]\nweight = " << toml_number(c.weight) << "\n";
      if (c.zone) {
        out << "zone = [" << toml_number(c.zone_low) << ", " << toml_number(c.zone_high) << "]\n";
      }
      if (std::isfinite(c.limit_low) != std::isfinite(c.limit_high)) {
        throw std::invalid_argument(
            "cv.limits = (one-sided), expected both limits finite (the file writes [low, high])");
      }
      if (std::isfinite(c.limit_low)) {
        out << "limits = [" << toml_number(c.limit_low) << ", " << toml_number(c.limit_high)
            << "]\n";
      }
    }
  }
  for (const PiLoop& l : file.pairing) {
    out << "\n[[pairing]]\ncv = " << l.cv + 1 << "\nmv = " << l.mv + 1
        << "\nkc = " << toml_number(l.gain) << "\nti_min = " << toml_number(l.integral_min) << "\n";
  }
  return out.str();
}

}  // namespace excite::sim::control
