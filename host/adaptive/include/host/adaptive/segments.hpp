// SPDX-License-Identifier: MIT
#pragma once
// The segments of an adaptive test (issue 26 §3): pieces of one long PRBS design, each the
// next rows of the same m-sequences, mixed for the directions the test needs now.
//
// A segment's sources are those of the prior's prbsUnc and prbsSimDir designs: n shifted
// copies of one m-sequence (host/design/binary_presets.cpp), the same whatever G(0) is
// (A1 fixes them from τ_L, τ_H and n). Cutting rows [first, first + rows) of such a design
// advances every source's shift by first / hold bits (firmware/signal: bit b = (shift +
// ⌊t / hold⌋) mod N_s), so segment k + 1 continues segment k's sequences exactly; only the mix
// changes from one segment to the next:
//   - plain:      the prior's prbsUnc mix (one source per input, sized as designed);
//   - directions: u = c V̂ Σ̂⁻¹ diag(w) s, the prbsSimDir mix designed from the identified
//                 G(0) (5.2.2), its column i weighted by w_i (confidence.hpp).
// Every segment has the design's channels, limits and sample time, so a gateway takes it as
// its next segment (firmware/app: the segment inbox).

#include <Eigen/Core>

#include <cstdint>
#include <string>

#include "firmware/plan/plan.hpp"
#include "host/design/presets.hpp"
#include "host/design/prior_knowledge.hpp"

namespace excite::host {

/// Rows [first_row, first_row + rows) of `design`, whose every source is a PRBS over the whole
/// table from row 0. Throws std::invalid_argument naming the field when a source is not
/// such a PRBS, first_row is not a whole number of bits of every source, or rows is 0.
plan::Plan cut_segment(const plan::Plan& design, std::uint64_t first_row, std::uint32_t rows);

/// Multiplies mix column (source) i of `plan` by weights(i): sizes must agree (else
/// std::invalid_argument); weights finite and ≥ 0.
void weight_sources(plan::Plan& plan, const Eigen::VectorXd& weights);

/// Multiplies every mix entry by `scale` (≥ 0, finite).
void scale_mix(plan::Plan& plan, double scale);

/// Sets the plan's provenance to `text`, cut to the plan format's 127 bytes.
void set_provenance(plan::Plan& plan, const std::string& text);

/// The long designs the segments are cut from.
struct SegmentSources {
  Design plain;  // the prior's prbsUnc
};

/// The prior's prbsUnc. Throws std::invalid_argument from the design for a bad prior.
SegmentSources segment_sources(const PriorKnowledge& prior);

/// prbsSimDir designed from `identified_gain` in place of the prior's G(0) (square, full
/// rank; else std::invalid_argument from the design).
Design directional_design(const PriorKnowledge& prior, const Eigen::MatrixXd& identified_gain);

/// The whole-bit segment length closest above `minutes` (at least one bit) for `design`'s
/// PRBS: a multiple of every source's hold.
std::uint32_t whole_bit_rows(const plan::Plan& design, double minutes);

}  // namespace excite::host
