// SPDX-License-Identifier: MIT
#pragma once
// An identified transfer-function matrix of (6.1.1) elements, one MISO row per output
// (SPEC §6), with what the data said about each element.
//
// Data convention everywhere in host/identify: U is N × n (row k = sample k, column i =
// input i), Y is N × p; deviation variables; the plant at rest before k = 0.

#include <Eigen/Dense>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/element.hpp"

namespace excite::host {

enum class ElementStatus {
  identified,        // parameters estimated; standard errors available unless at a bound
  weak_gain,         // estimated, but |K| < 2·SE(K): the data cannot pin the dynamics down
  input_not_moved,   // input i is zero throughout the data: no parameters (NaN)
  input_collinear,   // input i is a linear combination of other inputs: not separable (NaN)
  output_not_moved,  // output j is constant: nothing to fit (NaN)
};

/// Short name: "identified", "weak_gain", "input_not_moved", …
const char* to_string(ElementStatus status);

/// How far an element can be trusted (grade.hpp states the rule): A good for control, B
/// usable, C doubtful, D not usable.
enum class Grade { A, B, C, D };

/// "A", "B", "C" or "D".
const char* to_string(Grade grade);

/// Which of its bounds a parameter ended on.
enum class Bound : unsigned char { none, lower, upper };

/// An interval of a gain.
struct GainBounds {
  double lower = 0.0;
  double upper = 0.0;
};

/// A gain's 95 % interval wider than K ± 1.96·SE, and why (gain_profile.hpp,
/// project_gains_near_zero).
struct ProjectedGain {
  GainBounds bounds;
  std::string why;
};

struct ElementEstimate {
  ElementModel value;      // structure and parameters; NaN fields when not estimated (status)
  ElementModel std_error;  // 1σ; NaN when not available (not estimated, at a bound, or not a
                           // parameter of the structure)
  std::array<Bound, kParameters> at_bound{};  // the bound a parameter ended on (by Parameter)
  /// The element's block of the row's parameter covariance σ̂² (JᵀJ)⁺ over the directions
  /// the data determine (indexed by Parameter; its diagonal is std_error² except where
  /// std_error is inf: a direction the output does not depend on is left out). NaN rows and
  /// columns for a parameter on a bound, not estimated or not in the structure.
  using Covariance = Eigen::Matrix<double, kParameters, kParameters>;
  Covariance covariance = Covariance::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The gain variance a χ²₁ profile added to the linearised one where the data do not
  /// determine the gain (gain_profile.hpp, add_gain_variance); 0 elsewhere.
  double profile_variance = 0.0;
  /// The gain's 95 % interval where a projection reaches it (gain_profile.hpp,
  /// project_gains_near_zero); empty elsewhere.
  std::optional<ProjectedGain> projected_gain;
  ElementStatus status = ElementStatus::identified;
  std::string reason;        // why the status is not `identified`; "" otherwise
  Grade grade = Grade::D;    // set by identify() (grade.hpp)
  std::string grade_reason;  // what kept it from A ("" for A)

  /// The parameters that ended on a bound, each as "Tp1 = 150 (upper bound)" or
  /// "Td = 0 (lower bound)" (the lower bounds of T_d and T_p are 0; K has none; ζ lies in
  /// [kMinDamping, 1]; T_z in [−max time constant, max time constant]).
  std::vector<std::string> on_bound() const;
  /// True when T_d, a T_p, T_n or |T_z| ended on its upper bound (not 0; ζ = 1 is not one: it
  /// is the critically damped limit of the structure).
  bool on_upper_bound() const;

  /// True when value can be simulated (identified or weak_gain).
  bool estimated() const {
    return status == ElementStatus::identified || status == ElementStatus::weak_gain;
  }
};

/// The gain's reported 95 % interval: K ± 1.96·SE, widened to hold the projected interval
/// where the element has one (an interval of the gain's rate for an integrator). NaN bounds
/// where the element is not estimated or its gain has no finite SE and no projection.
GainBounds gain_interval_95(const ElementEstimate& e);

/// p × n matrix of estimates; T in minutes.
struct IdentifiedModel {
  int inputs = 0;
  int outputs = 0;
  double sample_time_min = 0.0;
  std::vector<ElementEstimate> elements;  // row-major: elements[out * inputs + in]
  /// Per output j, the n × n covariance of that row's gains K_j1 … K_jn (one MISO fit, so
  /// gains of one row are correlated; rows are fitted apart and taken as independent).
  /// NaN rows/columns for an element not estimated or with K on a bound; empty when unknown
  /// (a model read from a file without it).
  std::vector<Eigen::MatrixXd> gain_covariance;

  const ElementEstimate& element(int out, int in) const {
    return elements[static_cast<std::size_t>(out * inputs + in)];
  }
  ElementEstimate& element(int out, int in) {
    return elements[static_cast<std::size_t>(out * inputs + in)];
  }
  /// G(0) of every element (NaN where not estimated, ±inf for an integrator), p × n.
  Eigen::MatrixXd static_gain() const;
};

/// Ŷ (N × p) of the model driven by U (N × n, same sample time). An element that was not
/// estimated contributes NaN to its output when its input moves, 0 otherwise.
/// Throws std::invalid_argument when U has the wrong number of columns.
Eigen::MatrixXd simulate(const IdentifiedModel& model, const Eigen::MatrixXd& U);

}  // namespace excite::host
