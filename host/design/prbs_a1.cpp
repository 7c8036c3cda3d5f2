// SPDX-License-Identifier: MIT
#include "host/design/prbs_a1.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "firmware/signal/mseq.hpp"

namespace excite::host {
namespace {

std::string format(const char* fmt, auto... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

int smallest_register_length(double min_period) {
  for (int n_r = signal::kMinRegisterLength; n_r <= signal::kMaxRegisterLength; ++n_r) {
    if (static_cast<double>(signal::mseq_period(n_r)) >= min_period) return n_r;
  }
  throw std::invalid_argument(format(
      "PRBS period: need N_s >= %.1f, beyond the longest m-sequence (n_r = 31)", min_period));
}

}  // namespace

std::uint32_t channel_shift(double shift_intervals, std::uint32_t period_bits, int channels) {
  const auto ceil_d = static_cast<std::uint32_t>(std::ceil(shift_intervals));
  const auto n = static_cast<std::uint32_t>(channels);
  return n * ceil_d <= period_bits ? ceil_d : period_bits / n;
}

PrbsDesign design_prbs(const PriorKnowledge& prior) {
  validate(prior);
  PrbsDesign d;
  const double T = prior.sample_time_min;
  const int n = prior.input_count();

  // (4.2.3) T_sw ≤ 2.8 τ_L / α, the longest whole number of samples.
  const double tsw_bound = 2.8 * prior.tau_low_min / prior.alpha;
  const double hold = std::floor(tsw_bound / T + 1e-9);
  if (hold < 1.0) {
    throw std::invalid_argument(
        format("switching time (4.2.3): T_sw <= 2.8*tau_L/alpha = %.4g min is shorter than the "
               "sample time T = %.4g min; choose a shorter sample time",
               tsw_bound, T));
  }
  d.hold_samples = static_cast<std::uint32_t>(hold);
  d.switch_time_min = hold * T;
  d.explanation.push_back(
      format("(4.2.3) T_sw <= 2.8*tau_L/alpha = 2.8*%g/%g = %.3f min -> T_sw = %g min (%u samples "
             "of T = %g min)",
             prior.tau_low_min, prior.alpha, tsw_bound, d.switch_time_min, d.hold_samples, T));

  // (4.2.4) D = 5 τ_H / T_sw, kept real in (4.2.5).
  d.shift_intervals = 5.0 * prior.tau_high_min / d.switch_time_min;
  d.explanation.push_back(format("(4.2.4) D = 5*tau_H/T_sw = 5*%g/%g = %.4g switching intervals",
                                 prior.tau_high_min, d.switch_time_min, d.shift_intervals));

  // (4.2.5)–(4.2.7) smallest n_r with N_s ≥ max(2πβτ_H/T_sw, n·D).
  const double settling =
      2.0 * std::numbers::pi * prior.beta * prior.tau_high_min / d.switch_time_min;
  const double shifted = n * d.shift_intervals;
  d.register_length = smallest_register_length(std::max(settling, shifted));
  d.period_bits = signal::mseq_period(d.register_length);
  d.explanation.push_back(
      format("(4.2.5) N_s >= max(2*pi*beta*tau_H/T_sw, n*D) = max(%.2f, %d*%.4g = %.2f) -> n_r = "
             "%d, N_s = %u",
             settling, n, d.shift_intervals, shifted, d.register_length, d.period_bits));

  // Simultaneous designs: one sequence as long as the sequential experiment (thesis 6.3).
  const double sequential_bits = static_cast<double>(n) * d.period_bits;
  d.long_register_length = smallest_register_length(sequential_bits);
  d.long_period_bits = signal::mseq_period(d.long_register_length);
  d.experiment_samples = d.long_period_bits * d.hold_samples;
  d.explanation.push_back(format(
      "(6.3)   simultaneous PRBS as long as the sequential one: N_s >= n*N_s = %d*%u = %.0f -> "
      "n_r = %d, N_s = %u; experiment %u samples = %g min",
      n, d.period_bits, sequential_bits, d.long_register_length, d.long_period_bits,
      d.experiment_samples, d.experiment_samples * T));

  // (4.2.8) T ≤ T_sw, about T_sw / 4.
  d.explanation.push_back(format("(4.2.8) T = %g min <= T_sw = %g min%s", T, d.switch_time_min,
                                 d.hold_samples >= 4
                                     ? " (at least T_sw/4, as Ljung recommends)"
                                     : "; Ljung recommends T ~ T_sw/4: consider a shorter T"));
  return d;
}

}  // namespace excite::host
