// SPDX-License-Identifier: MIT
#pragma once
// The controller in excite-plant's loop (README, "Closed loop"). Each plant sample k: the
// operator's switch, the gateway's MV test offsets and CV setpoint offsets and the CVs
// measured at the previous sample in; the MVs the plant gets out, with what a commercial
// stepper reads back: the controller's move, the applied MV, each MV's status, the
// setpoints in force and the controller's mode. Deviations from the operating point
// throughout (the plant's units). The MV the plant gets is u = clamp(u_ctrl + offset,
// [min, max]) with the controller file's MV limits: the offset is what the DCS adds to its
// controller's output (CLOSED-LOOP.md).
//
// Life cycle: the constructor may allocate and throw; step() and clear_offsets() allocate
// nothing and throw nothing (the plant's real-time loop calls them).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "firmware/runlog/format.hpp"
#include "sim/control/controller.hpp"

namespace excite::sim::server {

/// The controller's mode, the run log's (off 0, control 1, test 2, suspended 3: its register
/// value, uint16; its text runlog::to_text).
using LoopMode = runlog::LoopMode;
/// Each MV's status, the run log's (ok 0, clamped low 1, clamped high 2, windup 3: the
/// controller plus the offset ask beyond a limit and the clamp cuts it, manual 4: the
/// controller is off and the MV is the operator's, held); its register value, uint16.
using LoopStatus = runlog::MvState;

class ClosedLoop {
 public:
  /// `mv_min`/`mv_max`: one per MV, deviations (±infinity: none). Throws
  /// std::invalid_argument when their sizes are not the controller's.
  ClosedLoop(std::unique_ptr<control::Controller> controller, std::vector<double> mv_min,
             std::vector<double> mv_max);

  int inputs() const noexcept { return static_cast<int>(applied_.size()); }
  int outputs() const noexcept { return static_cast<int>(setpoints_.size()); }

  /// Sample k. `y`: the CVs measured at sample k − 1 (the loop's one sample of delay: the
  /// controller file's `model.delay_samples = 1`); `switch_value`: the operator's switch
  /// register (1 or 2 control, 0 off, 3 suspended; any other value keeps the last request).
  /// In control the controller steps with y_sp = the setpoint offsets and the MV offsets as
  /// known moves; off (manual), every MV holds where it was (status manual) and the
  /// controller stands still; suspended, the controller stands still and its last output is
  /// applied without the offsets. Back in control it goes on from its last output (the MV
  /// was held there: no bump). Sizes: y and sp_offsets outputs(), mv_offsets inputs().
  void step(std::span<const double> y, std::uint16_t switch_value,
            std::span<const double> mv_offsets, std::span<const double> sp_offsets) noexcept;

  /// The watchdog's safe state: every offset at zero from now on (the caller zeroes the
  /// registers), the controller kept in control: the applied MVs become the controller's
  /// moves at once (as a DCS drops its offset; in manual they stay held), a mode of test
  /// becomes control and the setpoints in force return to zero.
  void clear_offsets() noexcept;

  LoopMode mode() const noexcept { return mode_; }
  std::span<const double> moves() const noexcept { return moves_; }          // u_ctrl
  std::span<const double> applied() const noexcept { return applied_; }      // du the plant got
  std::span<const double> setpoints() const noexcept { return setpoints_; }  // y_sp in force
  std::span<const double> offsets() const noexcept { return offsets_; }      // offsets applied
  std::span<const LoopStatus> status() const noexcept { return status_; }
  /// Steps the controller reported `held` or `qp_fallback` (said at stop).
  std::uint64_t irregular_steps() const noexcept { return irregular_steps_; }

 private:
  void apply(std::span<const double> offsets) noexcept;

  std::unique_ptr<control::Controller> controller_;
  std::vector<double> min_;
  std::vector<double> max_;
  std::vector<double> moves_;
  std::vector<double> applied_;
  std::vector<double> setpoints_;
  std::vector<double> offsets_;
  std::vector<double> zeros_;
  std::vector<LoopStatus> status_;
  LoopMode requested_ = LoopMode::control;
  LoopMode mode_ = LoopMode::control;
  std::uint64_t irregular_steps_ = 0;
};

}  // namespace excite::sim::server
