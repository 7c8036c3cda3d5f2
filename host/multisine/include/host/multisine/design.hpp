// SPDX-License-Identifier: MIT
#pragma once
// Multisine design procedures A2 (standard, Table 4.5: 4.4.26–4.4.28) and A3 (zippered,
// Table 4.6: 4.4.29–4.4.31, with the consistency inequalities 4.4.14–4.4.17 and 4.4.25;
// SPEC §1, §2, §8). They choose the sample time T, the period N_s (samples) and the number
// of band lines n_s (per channel) from the prior knowledge. Every inequality is checked and
// written into `explanation` with its numbers; when one fails the design throws
// std::invalid_argument naming the inequality, both sides and the margin.
//
// Units: τ_L, τ_H and T in one time unit (minutes in the case studies); ω in rad per that
// unit. The band is ω_L = 1/(β τ_H) … ω_H = α/τ_L (4.4.1, 4.4.10).

#include <cstdint>
#include <string>
#include <vector>

namespace excite::host::multisine {

struct DesignRequest {
  double tau_low = 0.0;        // τ_L, smallest dominant time constant
  double tau_high = 0.0;       // τ_H, largest dominant time constant
  double alpha = 0.0;          // α: ω_H = α/τ_L
  double beta = 0.0;           // β: ω_L = 1/(β τ_H)
  std::uint32_t channels = 1;  // n
  std::uint32_t delta = 0;     // δ, notch (A3 only): low snow slots per channel
  /// q (A3 only): shared (correlated) slots per block of the modified zippered spectrum
  /// (4.4.21); A3 then runs with n + q interleaved slots in place of n.
  std::uint32_t shared_slots = 0;
  /// T; 0 lets the design choose T = 0.6/ω_H (thesis remark after Table 4.6).
  double sample_time = 0.0;
  /// Capacity: longest period the caller can hold, in samples; 0 = no limit.
  std::uint32_t max_period = 0;
};

struct MultisineDesign {
  double sample_time = 0.0;  // T
  double omega_low = 0.0;    // ω_L
  double omega_high = 0.0;   // ω_H
  std::uint32_t period = 0;  // N_s, samples
  std::uint32_t lines = 0;   // n_s: band lines per channel
  std::uint32_t delta = 0;   // δ
  std::uint32_t slots = 1;   // interleaved slots per block: 1 (A2), n (A3), n + q (A3 modified)
  std::vector<std::string> explanation;  // one line per step and inequality, with numbers
};

/// A2 (Table 4.5): T < π/ω_H (4.4.26); smallest N_s ≥ 2π/(T ω_L) (4.4.27); smallest
/// n_s ≥ N_s T ω_H / (2π) (4.4.28); lines 1 … n_s for every channel.
MultisineDesign design_standard(const DesignRequest& request);

/// A3 (Table 4.6) for n (+ q) slots: T < π/ω_H (4.4.29); smallest N_s ≥ 2π n(1+δ)/(T ω_L)
/// (4.4.30); smallest n_s ≥ N_s T ω_H/(2π n) − δ (4.4.31); then 4.4.14–4.4.17 (with m read
/// as n, SPEC §8) and 4.4.25 must hold.
MultisineDesign design_zippered(const DesignRequest& request);

}  // namespace excite::host::multisine
