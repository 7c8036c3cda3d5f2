// SPDX-License-Identifier: MIT
#pragma once
// One controller interface for every controller in the loop (DMC/QDMC, decentralised PI).
//
// Units and timing. All values are deviations from the operating point, in the plant's
// units (as everywhere in sim/): y(k) the CVs (outputs) sampled at kT, y_sp(k) their
// setpoints, known_offsets(k) what is added to the controller's output before the MVs
// (inputs) reach the plant (a test signal, MV dither), u_ctrl(k) the controller's output.
// The MV the plant receives is u(k) = u_ctrl(k) + known_offsets(k), held over
// [kT, (k+1)T). One call per sample, T = sample_time_min() minutes, in order; a loop that
// applies the output one or more samples later says so in the controller's model
// (StepModel::delayed, the controller file's `model.delay_samples`).
//
// Life cycle: construction may allocate and throw (bad settings: std::invalid_argument in the
// one message form); after it, step() and reset() allocate nothing, throw nothing and take
// bounded work (the plant server runs step() in real time); the same inputs from reset()
// give the same outputs (no randomness, no clock).

#include <cstdint>
#include <span>

namespace excite::sim::control {

/// What one step did. `held`: an input was not finite or had the wrong size, and u_ctrl is
/// the previous output (the model's state advances as if the controller had not moved).
/// `qp_fallback`: the QP stopped at its iteration cap (or, not expected by construction,
/// found its constraints contradictory); u_ctrl is the unconstrained move clipped into the
/// MV limits (a safe, not an optimal, move).
enum class StepStatus : std::uint8_t { ok, held, qp_fallback };

/// Each MV's status after a step (what a commercial stepper reads and logs).
enum class MvStatus : std::uint8_t {
  ok,
  clamped_low,   // the MV sits on its lower limit
  clamped_high,  // the MV sits on its upper limit
  move_limited,  // the step's move is its largest allowed move
};

const char* to_string(StepStatus s) noexcept;
const char* to_string(MvStatus s) noexcept;

struct StepReport {
  StepStatus status = StepStatus::ok;
  int qp_iterations = 0;       // active-set iterations (0 for PI and the unconstrained path)
  int active_constraints = 0;  // constraints active at the solution
};

class Controller {
 public:
  virtual ~Controller() = default;

  virtual int inputs() const noexcept = 0;   // n MVs
  virtual int outputs() const noexcept = 0;  // p CVs
  virtual double sample_time_min() const noexcept = 0;

  /// At rest at the operating point: u_ctrl = 0, every CV and offset 0 in the past.
  virtual void reset() noexcept = 0;

  /// Sample k: y (p values), y_sp (p values), known_offsets (n values) in, u_ctrl (n
  /// values) out. Wrong sizes or non-finite inputs: StepStatus::held (u_ctrl is written
  /// when it has n places).
  virtual StepReport step(std::span<const double> y, std::span<const double> y_sp,
                          std::span<const double> known_offsets,
                          std::span<double> u_ctrl) noexcept = 0;

  /// Each MV's status after the last step (n values; all ok after reset()).
  virtual std::span<const MvStatus> mv_status() const noexcept = 0;
};

}  // namespace excite::sim::control
