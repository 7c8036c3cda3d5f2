// SPDX-License-Identifier: MIT
#include "host/campaign/closed_loop_designs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "host/design/closed_loop_design.hpp"
#include "host/measures/gain_directions.hpp"
#include "sim/control/make_controller.hpp"

namespace excite::host {

void check_excitation(const std::string& excitation) {
  if (excitation != "setpoint" && excitation != "mv")
    throw std::invalid_argument("--excitation = " + excitation + ", expected setpoint or mv");
}

void check_directions(const std::string& directions, const std::string& excitation) {
  if (directions != "none" && directions != "output")
    throw std::invalid_argument("--directions = " + directions + ", expected none or output");
  if (directions == "output" && excitation != "setpoint") {
    throw std::invalid_argument("--directions = output with --excitation = " + excitation +
                                ", expected setpoint excitation (r along the prior's output "
                                "directions; an MV dither is the open-loop preset)");
  }
}

void check_switching(const std::string& switching) {
  if (switching != "loop" && switching != "plant")
    throw std::invalid_argument("--switching = " + switching + ", expected loop or plant");
}

std::vector<const PresetInfo*> closed_loop_presets(const std::vector<std::string>& names) {
  std::vector<const PresetInfo*> set;
  if (names.empty()) {
    for (const PresetInfo& p : presets())
      if (!p.uses_directions()) set.push_back(&p);
  }
  for (const std::string& name : names) {
    const PresetInfo& p = find_preset(name);
    if (p.uses_directions()) {
      throw std::invalid_argument("--designs = " + name +
                                  ", expected a plain preset (a directional one has no "
                                  "closed-loop design: the controller makes the rotation)");
    }
    set.push_back(&p);
  }
  return set;
}

void resolve_cv_limits(ClosedLoopDesignOptions& o, const sim::control::ControllerFile& file,
                       Eigen::Index outputs) {
  if (o.excitation != "setpoint" || o.cv_low.size() > 0) return;
  if (static_cast<Eigen::Index>(file.dmc.cv.size()) != outputs) {
    throw std::invalid_argument(
        "--limit = (none), expected CV test limits for a setpoint "
        "excitation (or a DMC controller file with [[cv]] limits)");
  }
  o.cv_low.resize(outputs);
  o.cv_high.resize(outputs);
  for (Eigen::Index c = 0; c < outputs; ++c) {
    o.cv_low(c) = file.dmc.cv[static_cast<std::size_t>(c)].limit_low;
    o.cv_high(c) = file.dmc.cv[static_cast<std::size_t>(c)].limit_high;
  }
}

Design design_closed_loop(const ClosedLoopDesignOptions& o, const PriorKnowledge& prior,
                          const PresetInfo& preset, const std::vector<std::string>& cv_names,
                          const sim::control::ControllerFile& file) {
  check_directions(o.directions, o.excitation);
  if (o.excitation == "mv") return design_mv_dither(prior, preset, 0);
  SetpointDesignRequest request;
  request.cv_names = cv_names;
  request.cv_low = o.cv_low;
  request.cv_high = o.cv_high;
  request.fraction = o.limit_fraction;
  request.along_output_directions = o.directions == "output";
  request.prbs_phase = o.prbs_phase;
  if (o.mv_fraction > 0.0) {  // the MVs' room, from the controller file
    const auto n = static_cast<Eigen::Index>(file.dmc.mv.size());
    request.mv_fraction = o.mv_fraction;
    request.mv_low.resize(n);
    request.mv_high.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      request.mv_low(i) = file.dmc.mv[static_cast<std::size_t>(i)].min;
      request.mv_high(i) = file.dmc.mv[static_cast<std::size_t>(i)].max;
    }
  }
  return design_setpoint_excitation(prior, preset, request, 0);
}

double mv_room_scale(const Eigen::MatrixXd& gain, const Eigen::MatrixXd& r,
                     const Eigen::VectorXd& mv_low, const Eigen::VectorXd& mv_high,
                     double mv_fraction) {
  if (mv_fraction <= 0.0 || mv_low.size() != gain.cols()) return 1.0;
  const Eigen::MatrixXd moves = gain.fullPivLu().solve(r.transpose());  // MV × row
  double alpha = 1.0;
  for (Eigen::Index i = 0; i < moves.rows(); ++i) {
    const double room = mv_fraction * std::min(-mv_low(i), mv_high(i));
    const double peak = moves.row(i).cwiseAbs().maxCoeff();
    if (peak > room) alpha = std::min(alpha, room / peak);
  }
  return alpha;
}

LoopPace at_the_loops_pace(const PriorKnowledge& prior, const Eigen::VectorXd& amplitude,
                           double mv_fraction, const sim::control::ControllerFile& file) {
  const auto model = sim::control::load_model(file);
  const auto controller = sim::control::make_controller(file, *model);
  ClosedLoopOptions loop;
  set_controller(loop, file, file.source);
  const Eigen::MatrixXd W = analyse_gain(prior.gain).output_directions;
  if (amplitude.size() != W.rows()) {
    throw std::invalid_argument("loop's pace: " + std::to_string(amplitude.size()) +
                                " CV amplitudes, expected " + std::to_string(W.rows()) +
                                " (one per output of the prior's G(0))");
  }
  const Eigen::VectorXd w = W.col(W.cols() - 1);
  double c = std::numeric_limits<double>::infinity();
  for (Eigen::Index j = 0; j < w.size(); ++j) {
    if (w(j) != 0.0) c = std::min(c, amplitude(j) / std::abs(w(j)));
  }
  Eigen::VectorXd step = c * w;
  step *= mv_room_scale(prior.gain, step.transpose(), loop.mv_min, loop.mv_max, mv_fraction);
  const int hold =
      static_cast<int>(std::ceil(4.0 * prior.beta * prior.tau_high_min / prior.sample_time_min));
  LoopPace pace{prior,
                closed_loop_speed(step, hold, prior.sample_time_min, *model, *controller, loop)};
  pace.prior.tau_low_min =
      std::clamp(pace.speed.time_constant_min, prior.tau_low_min, prior.tau_high_min);
  return pace;
}

std::string loop_pace_line(const LoopPace& pace, const PriorKnowledge& prior) {
  const auto minutes = [](double m) { return std::to_string(std::lround(m)); };
  return "the loop follows a switch of r along the prior's weakest output direction in " +
         std::string(pace.speed.reached ? "" : "more than ") +
         minutes(pace.speed.time_constant_min) +
         " min (63 %, on the controller's model): tau_L = " + minutes(pace.prior.tau_low_min) +
         " min (the plant's " + minutes(prior.tau_low_min) + ")";
}

Eigen::VectorXd cv_amplitude(const Eigen::VectorXd& low, const Eigen::VectorXd& high,
                             double fraction) {
  return (-low).cwiseMin(high) * fraction;
}

std::optional<LoopPace> setpoint_pace(const ClosedLoopDesignOptions& o, const PriorKnowledge& prior,
                                      const sim::control::ControllerFile& file) {
  check_switching(o.switching);
  if (o.excitation != "setpoint" || o.switching != "loop") return std::nullopt;
  return at_the_loops_pace(prior, cv_amplitude(o.cv_low, o.cv_high, o.limit_fraction),
                           o.mv_fraction, file);
}

}  // namespace excite::host
