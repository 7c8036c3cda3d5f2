// SPDX-License-Identifier: MIT
#pragma once
// A design before it becomes a recipe: scalar sources of unit size, the multisine lines
// they draw on, and the matrix that mixes them into the channels (recipe.hpp).

#include <Eigen/Core>

#include <cstdio>
#include <string>
#include <vector>

#include "firmware/signal/recipe.hpp"
#include "host/design/prbs_a1.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {

struct Composition {
  std::uint32_t samples = 0;            // experiment length N
  std::vector<signal::Source> sources;  // unit peak (binary ±1, steps ±1, multisines)
  std::vector<signal::Line> lines;      // multisine lines, referenced by the sources
  Eigen::MatrixXd mix;                  // channels × sources; empty: V·Σ⁻¹ (directions)
  std::vector<std::string> notes;       // how it was built, with numbers
};

/// What a composer may use: the prior knowledge, A1's PRBS design (it fixes N for every
/// design), and the gain analysis (null when G(0) is unknown).
struct DesignContext {
  const PriorKnowledge& prior;
  const PrbsDesign& prbs;
  const GainAnalysis* gains;
};

/// Steps and PRBS: presets 1–8 (binary_presets.cpp).
Composition compose_binary(std::string_view acronym, const DesignContext& context);

/// Multisines: presets 9–17 (multisine_presets.cpp).
Composition compose_multisine(std::string_view acronym, const DesignContext& context);

struct PlainMultisine;

/// A plain multisine on every input (multisine_presets.cpp).
Composition compose_plain_multisine(const PriorKnowledge& prior, const PlainMultisine& spec);

/// diag(a_j): the per-input amplitudes.
Eigen::MatrixXd amplitude_matrix(const PriorKnowledge& prior);

/// Requires G(0) for a directional preset; std::invalid_argument naming the preset otherwise.
const GainAnalysis& require_gains(const DesignContext& context, std::string_view acronym);

/// Low-amplitude share of the correlated designs (Zhu 2009, Lee & Rivera): the uncorrelated
/// part has this fraction of the amplitude of the part along v_n before common scaling.
inline constexpr double kCorrelatedLowShare = 1.0 / 3.0;

/// printf into a std::string (notes and messages).
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buffer[400];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

}  // namespace excite::host
