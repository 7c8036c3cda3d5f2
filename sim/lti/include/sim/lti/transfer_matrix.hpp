// SPDX-License-Identifier: MIT
#pragma once
// A p × n matrix of continuous elements G(s) with named inputs and outputs (SPEC §7).
// Time in minutes; u and y are deviation variables.

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "sim/lti/element.hpp"

namespace excite::sim {

class TransferMatrix {
 public:
  /// p outputs × n inputs; all elements zero; names y1…yp and u1…un.
  TransferMatrix(int outputs, int inputs);

  /// Parses rows of element strings (rows = outputs). Names may be empty (then u1…, y1…);
  /// otherwise they must match the matrix size and be unique and non-empty.
  /// Throws std::invalid_argument naming the row, column and text of a bad element.
  static TransferMatrix parse(const std::vector<std::vector<std::string>>& rows,
                              std::vector<std::string> input_names = {},
                              std::vector<std::string> output_names = {},
                              const ElementRules& rules = {});

  int inputs() const { return inputs_; }
  int outputs() const { return outputs_; }
  const std::vector<std::string>& input_names() const { return input_names_; }
  const std::vector<std::string>& output_names() const { return output_names_; }

  /// Element from input `in` to output `out` (0-based).
  const Element& element(int out, int in) const;
  void set_element(int out, int in, Element e);

  /// G(0), p × n.
  Eigen::MatrixXd static_gain() const;
  /// G(jω), ω in rad/min (any finite ω; G(−jω) is the conjugate of G(jω)), p × n.
  Eigen::MatrixXcd frequency_response(double omega_rad_per_min) const;

  /// "row 2 (y2), column 3 (u3)" for messages (0-based arguments, 1-based text).
  std::string describe_position(int out, int in) const;

 private:
  int outputs_;
  int inputs_;
  std::vector<Element> elements_;  // row-major, outputs_ × inputs_
  std::vector<std::string> input_names_;
  std::vector<std::string> output_names_;
};

}  // namespace excite::sim
