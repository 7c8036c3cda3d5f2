// SPDX-License-Identifier: MIT
#pragma once
// Choosing each element's structure (element.hpp; issue 18 §5) once the row has been fitted
// with two poles and a delay (6.1.1).
//
// The criterion is the Bayesian information criterion of the row's output error,
//   BIC = M ln(max(SSE, ε ‖y‖²) / M) + P ln M,
// M the scored rows, P the row's free parameters, ε = 1e-12: extra parameters must lower the
// output error by a factor e^{ln M / M} each (0.06 % per parameter at M = 15 000), and on
// noise-free data every structure that fits to rounding ties, so the fewest parameters win.
//
// The search, per row, greedy: each element's part of the output (the output minus the other
// elements' simulated parts and the trend) is fitted alone in every other structure from
// starts derived from its current parameters (structure_starts(); when screened again in a
// later round, from the end each structure reached last time); the structure that lowers
// that part's BIC most by more than 2 is a candidate. The largest candidate alone and all
// together are refitted with the whole row, the better kept when the row's BIC falls by more
// than 2, else the other candidates one at a time. Rounds repeat until no element
// changes (at most six rounds). A forced structure (--structure, or one per element) fits
// each element in it from the same starts, the best end kept. Last, on every path, two local
// optima the search does not leave are tried from their other side (structure_search.cpp,
// leave_local_optima): an element the row's others can compensate for (|K| < 5 SE, or its
// part below 5 % of the row's) from either sign, its lags at the row's other elements' time
// scale and a quarter of it, in its own structure and in two poles (a forced structure: its
// own only), each kept when it lowers the row's BIC; and a delay within 0.05 T of a whole
// sample from across that kink. Structures chosen, a row whose residual is then not white
// and depends on an input has the element(s) of that input restarted from every structure,
// the others released to two poles, and the rounds run again from a start that is kept
// (restart_misplaced_dynamics: dynamics that ended on the wrong element).

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "host/identify/miso_fit.hpp"

namespace excite::host {

/// Starts for a fit in structure `s` from an element g of any structure: the parameters it
/// shares, the others derived from g's time scales (a few damping ratios or zeros where the
/// structure has them). Every start lies inside parameter_range().
std::vector<ElementModel> structure_starts(const ElementModel& g, Structure s,
                                           const MisoBounds& bounds);

/// The row's BIC (above) for a fit with the given output error.
double row_criterion(double sse, double y_energy, Eigen::Index scored_rows,
                     Eigen::Index parameters);

struct StructureSearch {
  std::optional<Structure> forced;  // every element in this structure; nullopt: chosen per element
  std::vector<Structure> per_element;  // one per input of the row: each element forced to its
                                       // own; empty: `forced` decides
  int max_iterations = 200;            // of each joint row fit
};

/// The row's fit with each element in its chosen structure, starting from `two_poles`, the
/// row's fit in (6.1.1) (fit_miso's arguments as it was fitted with).
MisoResult choose_structures(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                             const std::vector<int>& inputs, MisoResult two_poles, double T_min,
                             const MisoBounds& bounds, const SampleLayout& layout,
                             const Eigen::MatrixXd& trend, const StructureSearch& search);

/// The same from `fitted`, the row's fit from a warm start with each element already in a
/// structure (IdentifyOptions::start): a forced structure is kept and only its local optima
/// left; chosen ones are searched from there as from the two-pole fit.
MisoResult continue_structures(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                               const std::vector<int>& inputs, MisoResult fitted, double T_min,
                               const MisoBounds& bounds, const SampleLayout& layout,
                               const Eigen::MatrixXd& trend, const StructureSearch& search);

}  // namespace excite::host
