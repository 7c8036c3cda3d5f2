// SPDX-License-Identifier: MIT
#pragma once
// Crest-factor minimisation of Guillaume et al. (1991) (SPEC §1, §2): the phases of the
// excited lines are chosen to minimise the L_p norm of the signal for an increasing
// sequence of p (Pólya: ‖x‖_p → ‖x‖_∞), so the peak falls while the amplitudes, hence the
// power spectrum, stay fixed. Each p is one L-BFGS run; signal and gradient come from one
// inverse and one forward real FFT per channel on an oversampled grid, so the crest factor
// of the continuous (band-limited) signal falls, not only that of the samples.
//
// Several channels: the objective is (1/p)·log Σ_c mean_m |x_c(m)/rms_c|^p, the L_p norm of
// all channels' normalised signals together, which tends to the WORST channel's crest
// factor as p → ∞. A shared source's phases are common to every channel that carries it.
//
// Snow (4.4.19, 4.4.20): with snow_power_fraction ρ > 0, each channel's reserved snow lines
// get free amplitude and phase, with their total power below ρ times the channel's band
// power (a smooth bound: c = √(2ρP) · w / √(1 + ‖w‖²)); the objective then divides by the
// RMS including snow, i.e. it minimises the crest factor itself.

#include <cstdint>
#include <span>
#include <vector>

#include "host/multisine/multisine_set.hpp"
#include "host/multisine/start_phases.hpp"

namespace excite::host::multisine {

/// How the optimiser evaluates signal and gradient. `direct` (O(lines · grid) sums) is the
/// baseline the benchmark compares the FFT against; both give the same numbers.
enum class Evaluation { fft, direct };

/// What the optimiser lowers when channels are optimised together (a set with shared
/// sources): the worst channel's crest factor, or the average of the channels' (both through
/// L_p norms, see the file comment).
enum class ChannelAggregate { worst, mean };


struct GuillaumeOptions {
  std::vector<double> norms{4, 8, 16, 32, 64, 128, 256, 512};  // p, increasing
  int iterations_per_norm = 40;                                // L-BFGS iterations per p
  /// Optimisation grid: next power of two ≥ 2 · oversampling · (max index + 1) points per
  /// period, i.e. ≥ 2·oversampling points per cycle of the highest line. The optimiser
  /// exploits the gaps between grid points, so the fine grid must be dense (16: the
  /// continuous crest factor is within ~0.5 % of the grid's).
  std::uint32_t oversampling = 16;
  /// Norms p ≤ coarse_until_norm run on the coarser grid of `coarse_oversampling` (cheap;
  /// they shape the signal, the high p set the peak).
  std::uint32_t coarse_oversampling = 4;
  double coarse_until_norm = 64.0;
  double snow_power_fraction = 0.0;  // ρ; 0 leaves the snow slots empty
  /// worst: F = (1/p) log Σ_c mean_m |x_c/rms_c|^p (→ log of the worst channel's crest
  /// factor); mean: F = (1/C) Σ_c (1/p) log mean_m |x_c/rms_c|^p (→ the mean of the channels'
  /// log crest factors). The best iterate is judged by the same aggregate.
  ChannelAggregate aggregate = ChannelAggregate::worst;
  Evaluation evaluation = Evaluation::fft;
  /// Sets with shared sources: the starts tried, in order (ties keep the earlier). Sets
  /// without are optimised channel by channel from the given phases.
  std::vector<StartPhases> starts{StartPhases::given};
  /// Sets with shared sources, after the joint optimisation: each channel's own lines
  /// optimised again for that channel's crest factor alone, the shared phases held (a
  /// channel's own lines move no other channel, so no channel gets worse).
  bool polish_own_lines = false;
};

struct GuillaumeReport {
  std::uint32_t grid = 0;             // points per period of the optimisation grid
  int evaluations = 0;                // objective + gradient evaluations
  std::vector<double> cf_start;       // per channel, on the optimisation grid
  std::vector<double> cf_final;       // per channel, on the optimisation grid
  std::vector<double> snow_fraction;  // per channel: snow power / band power
  /// Per start tried (GuillaumeOptions::starts, in order): each channel's crest factor on the
  /// optimisation grid at the end of that start's optimisation (before any polish).
  std::vector<std::vector<double>> cf_by_start;
  std::size_t best_start = 0;  // the start kept
};

/// Optimises the free phases (and snow) of `start`, whose phases are the starting point
/// (Schroeder in the allocations). Returns the best iterate seen, by worst-channel (or,
/// with aggregate = mean, average) crest factor on the optimisation grid, so the result is
/// never worse than the start there.
/// Snow lines the optimiser filled are appended to their channel's own lines (sorted by
/// index) and removed from `snow`. Throws std::invalid_argument on an invalid set, an
/// empty or non-increasing p sequence, p < 2, or ρ outside [0, 1].
MultisineSet guillaume(const MultisineSet& start, const GuillaumeOptions& options,
                       GuillaumeReport* report = nullptr);

/// One channel: the lines' amplitudes fixed, their phases optimised from the given ones.
std::vector<Line> guillaume(std::span<const Line> start, std::uint32_t period,
                            const GuillaumeOptions& options, GuillaumeReport* report = nullptr);

}  // namespace excite::host::multisine
