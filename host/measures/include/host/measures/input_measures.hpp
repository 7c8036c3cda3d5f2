// SPDX-License-Identifier: MIT
#pragma once
// Plant-friendliness of input sequences (SPEC §5, thesis 4.3). They depend on the inputs
// only, not on the plant.

#include <Eigen/Core>

#include <vector>

namespace excite::host {

/// Measures of one channel's sequence x(k), k = 1…N.
struct ChannelMeasures {
  double phi = 0.0;         // Φ (4.3.1): (1 − n_switches/(N−1))·100 %
  double phi_smooth = 0.0;  // Φ_i (4.3.3): 1 − Σ(Δx)² / ((N−1)·max(Δx)²); 1 for a constant
  double peak_factor = 0.0;   // (4.3.4): (x_max − x_min) / (2√2·x_RMS)
  double rms = 0.0;           // (4.3.5)
  double crest_factor = 0.0;  // (4.3.6): max|x| / x_RMS
  double pips = 0.0;          // (4.3.7): 200 %·sqrt(x_RMS² − x_mean²) / (x_max − x_min)
  double min = 0.0;
  double max = 0.0;
  double max_step = 0.0;  // max |x(k) − x(k−1)|
};

/// Per channel and averaged over channels (the average of each field).
struct InputMeasures {
  std::vector<ChannelMeasures> channels;
  ChannelMeasures average;
};

/// Measures of one channel. A constant channel has Φ = 100 %, Φ_i = 1; measures that divide
/// by zero (crest factor and peak factor of an all-zero channel, PIPS of a constant one)
/// are NaN. Precondition: x.size() ≥ 2.
ChannelMeasures measure_channel(const Eigen::Ref<const Eigen::VectorXd>& x);

/// Measures of every column of `table` (N samples × n channels) and their average.
InputMeasures measure_inputs(const Eigen::Ref<const Eigen::MatrixXd>& table);

/// Crest factor (4.3.6) of each channel over its active span, from its first to its last
/// non-zero sample (a multisine's whole periods, a sequential channel's own slot),
/// averaged over the channels that move; NaN when none moves. The experiment's crest
/// factor of a channel active for a fraction f of it is this one divided by √f.
double active_crest_factor_avg(const Eigen::Ref<const Eigen::MatrixXd>& table);

}  // namespace excite::host
