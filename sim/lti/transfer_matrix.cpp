// SPDX-License-Identifier: MIT
#include "sim/lti/transfer_matrix.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "sim/lti/parse_element.hpp"

namespace excite::sim {
namespace {

std::vector<std::string> default_names(char prefix, int count) {
  std::vector<std::string> names;
  for (int i = 1; i <= count; ++i) names.push_back(prefix + std::to_string(i));
  return names;
}

void check_names(const std::vector<std::string>& names, int expected, const char* what) {
  if (static_cast<int>(names.size()) != expected) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(names.size()) +
                                " names given, expected " + std::to_string(expected));
  }
  std::set<std::string> seen;
  for (const std::string& n : names) {
    if (n.empty()) throw std::invalid_argument(std::string(what) + ", expected non-empty names");
    if (!seen.insert(n).second) {
      throw std::invalid_argument(std::string(what) + ": name \"" + n +
                                  "\" appears twice, expected unique names");
    }
  }
}

}  // namespace

TransferMatrix::TransferMatrix(int outputs, int inputs)
    : outputs_(outputs),
      inputs_(inputs),
      input_names_(default_names('u', inputs)),
      output_names_(default_names('y', outputs)) {
  if (outputs < 1 || inputs < 1) {
    throw std::invalid_argument("transfer matrix size " + std::to_string(outputs) + " × " +
                                std::to_string(inputs) + ", expected at least 1 × 1");
  }
  elements_.resize(static_cast<std::size_t>(outputs) * static_cast<std::size_t>(inputs));
}

TransferMatrix TransferMatrix::parse(const std::vector<std::vector<std::string>>& rows,
                                     std::vector<std::string> input_names,
                                     std::vector<std::string> output_names,
                                     const ElementRules& rules) {
  if (rows.empty() || rows.front().empty()) {
    throw std::invalid_argument("transfer matrix G: no rows, expected p rows of n elements");
  }
  const int p = static_cast<int>(rows.size());
  const int n = static_cast<int>(rows.front().size());
  for (int i = 0; i < p; ++i) {
    const auto len = static_cast<int>(rows[static_cast<std::size_t>(i)].size());
    if (len != n) {
      throw std::invalid_argument("transfer matrix G row " + std::to_string(i + 1) + ": " +
                                  std::to_string(len) + " elements, expected " + std::to_string(n) +
                                  " like row 1");
    }
  }
  TransferMatrix g(p, n);
  if (!input_names.empty()) {
    check_names(input_names, n, "inputs");
    g.input_names_ = std::move(input_names);
  }
  if (!output_names.empty()) {
    check_names(output_names, p, "outputs");
    g.output_names_ = std::move(output_names);
  }
  for (int i = 0; i < p; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::string context = "G " + g.describe_position(i, j);
      g.set_element(i, j,
                    parse_element(rows[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)],
                                  context, rules));
    }
  }
  return g;
}

const Element& TransferMatrix::element(int out, int in) const {
  if (out < 0 || out >= outputs_ || in < 0 || in >= inputs_) {
    throw std::out_of_range("transfer matrix element (" + std::to_string(out) + ", " +
                            std::to_string(in) + ") outside " + std::to_string(outputs_) + " × " +
                            std::to_string(inputs_));
  }
  return elements_[static_cast<std::size_t>(out * inputs_ + in)];
}

void TransferMatrix::set_element(int out, int in, Element e) {
  (void)element(out, in);  // bounds check
  elements_[static_cast<std::size_t>(out * inputs_ + in)] = std::move(e);
}

Eigen::MatrixXd TransferMatrix::static_gain() const {
  Eigen::MatrixXd g(outputs_, inputs_);
  for (int i = 0; i < outputs_; ++i) {
    for (int j = 0; j < inputs_; ++j) g(i, j) = element(i, j).static_gain();
  }
  return g;
}

Eigen::MatrixXcd TransferMatrix::frequency_response(double omega_rad_per_min) const {
  if (!std::isfinite(omega_rad_per_min)) {
    throw std::invalid_argument("frequency " + std::to_string(omega_rad_per_min) +
                                " rad/min, expected a finite value");
  }
  Eigen::MatrixXcd g(outputs_, inputs_);
  for (int i = 0; i < outputs_; ++i) {
    for (int j = 0; j < inputs_; ++j) g(i, j) = element(i, j).frequency_response(omega_rad_per_min);
  }
  return g;
}

std::string TransferMatrix::describe_position(int out, int in) const {
  return "row " + std::to_string(out + 1) + " (" + output_names_[static_cast<std::size_t>(out)] +
         "), column " + std::to_string(in + 1) + " (" + input_names_[static_cast<std::size_t>(in)] +
         ")";
}

}  // namespace excite::sim
