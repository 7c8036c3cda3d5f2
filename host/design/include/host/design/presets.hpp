// SPDX-License-Identifier: MIT
#pragma once
// The designs of the case study (SPEC §4, thesis Table 6.1) as named presets, built from
// prior knowledge into a plan the gateway can stream.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "host/design/prbs_a1.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/design/table.hpp"

namespace excite::host {

struct PresetInfo {
  int number;                // experiment number of Table 6.1
  std::string_view acronym;  // e.g. "prbsSimDir"
  std::string_view summary;
  std::string_view reference;  // directional designs: the input design whose static output
                               // size they match (host/README.md); empty for input designs

  bool uses_directions() const { return !reference.empty(); }  // needs G(0)
};

/// Every preset this build designs, in the order of Table 6.1.
const std::vector<PresetInfo>& presets();

/// The preset named `acronym`; std::invalid_argument listing the known ones otherwise.
const PresetInfo& find_preset(std::string_view acronym);

/// A designed experiment: the plan (the recipe plus its metadata), its table as the
/// gateway will generate it, and why each number is what it is.
struct Design {
  std::unique_ptr<plan::Plan> plan;
  Table table;
  PrbsDesign prbs;
  std::vector<std::string> notes;  // A1's inequalities, then sequencing and scaling
  double limit_scale = 1.0;        // < 1: the whole design was scaled by this to fit the
                                   // input limits (directions preserved)
};

/// A single multisine given by its lines, for trying phase methods on a plain spectrum
/// (design = "multisine" in a spec): equal-amplitude lines first_line … last_line of a
/// `period`-sample period, `periods` whole periods, the same signal on every input scaled
/// to peak at the input's amplitude.
struct PlainMultisine {
  std::uint32_t period = 0;          // samples
  std::uint32_t first_line = 1;      // DFT-grid index ≥ 1
  std::uint32_t last_line = 1;       // < period / 2
  std::string phases = "guillaume";  // schroeder (4.4.8), linear (4.4.3), random, guillaume
  std::uint64_t seed = 1;            // random phases
  std::uint32_t periods = 1;
};

/// Designs a plain multisine (validate_inputs only: no time constants needed).
Design design_plain_multisine(const PriorKnowledge& prior, const PlainMultisine& spec,
                              std::uint64_t created_unix_s);

/// Designs `preset` from validated prior knowledge (directional presets need its gain).
/// `created_unix_s` stamps the plan's metadata.
Design design_preset(const PriorKnowledge& prior, const PresetInfo& preset,
                     std::uint64_t created_unix_s);

}  // namespace excite::host
