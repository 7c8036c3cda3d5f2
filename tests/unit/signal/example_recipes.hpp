// SPDX-License-Identifier: MIT
#pragma once
// Recipes shared by the signal and plan tests and the signal bench: small, explicit
// builders of the SPEC §4 shapes (4 channels × 4080 samples, PRBS T_sw = 16 samples).

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <random>

#include "firmware/signal/recipe.hpp"

namespace excite::signal::testing {

/// A heap-held recipe (a Recipe is about 115 kB; tests keep it off the stack).
inline std::unique_ptr<Recipe> empty_recipe(std::uint32_t channels, std::uint32_t samples) {
  auto recipe = std::make_unique<Recipe>();
  recipe->channels = channels;
  recipe->samples = samples;
  return recipe;
}

/// Appends a PRBS source over the whole table; returns its index.
inline std::uint32_t add_prbs(Recipe& recipe, std::uint8_t n_r, double amplitude,
                              std::uint32_t hold, std::uint32_t shift) {
  const std::uint32_t i = recipe.source_count++;
  Source& s = recipe.sources[i];
  s.kind = SourceKind::prbs;
  s.start = 0;
  s.length = recipe.samples;
  s.prbs = {n_r, amplitude, hold, shift};
  return i;
}

/// Appends a step source with the given (level, length) segments in [start, start+length).
inline std::uint32_t add_steps(Recipe& recipe, std::uint32_t start, std::uint32_t length,
                               std::initializer_list<Segment> segments) {
  const std::uint32_t i = recipe.source_count++;
  Source& s = recipe.sources[i];
  s.kind = SourceKind::steps;
  s.start = start;
  s.length = length;
  for (const Segment& seg : segments) s.steps.segments[s.steps.segment_count++] = seg;
  return i;
}

/// Appends a multisine of `count` lines with distinct random indices in [1, period/2),
/// random amplitudes in [0.5, 1] and phases in [−π, π] (seeded), over the whole table.
inline std::uint32_t add_random_multisine(Recipe& recipe, std::uint32_t period, std::uint32_t count,
                                          std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> index(1, (period - 1) / 2);
  std::uniform_real_distribution<double> amplitude(0.5, 1.0);
  std::uniform_real_distribution<double> phase(-std::numbers::pi, std::numbers::pi);
  const std::uint32_t i = recipe.source_count++;
  Source& s = recipe.sources[i];
  s.kind = SourceKind::multisine;
  s.start = 0;
  s.length = recipe.samples;
  s.multisine = {period, recipe.line_count, count};
  for (std::uint32_t l = 0; l < count; ++l) {
    recipe.lines[recipe.line_count++] = {index(rng), amplitude(rng), phase(rng)};
  }
  return i;
}

/// A dense, well-conditioned 4×4 mix (a rotation-like matrix, all entries nonzero).
inline void set_dense_mix(Recipe& recipe) {
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    for (std::uint32_t i = 0; i < recipe.source_count; ++i) {
      recipe.mix[c][i] = std::cos(0.7 * (c + 1) + 1.3 * i) / 2.0;
    }
  }
}

/// SPEC §4 shape: 4 channels × 4080 samples; two shifted PRBS (n_r = 8, hold 16,
/// shifts 0 and 64 bits), two multisines of 60 lines on a 4080-sample period, a
/// step sequence in a window; dense mix.
inline std::unique_ptr<Recipe> mixed_case_study_recipe() {
  auto recipe = empty_recipe(4, 4080);
  add_prbs(*recipe, 8, 1.0, 16, 0);
  add_prbs(*recipe, 8, 1.0, 16, 64);
  add_random_multisine(*recipe, 4080, 60, 1);
  add_random_multisine(*recipe, 4080, 60, 2);
  add_steps(*recipe, 330, 1320, {{1.0, 330}, {-1.0, 330}, {0.5, 330}});
  set_dense_mix(*recipe);
  return recipe;
}

}  // namespace excite::signal::testing
