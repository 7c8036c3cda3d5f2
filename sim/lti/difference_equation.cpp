// SPDX-License-Identifier: MIT
#include "sim/lti/difference_equation.hpp"

#include <array>
#include <utility>

namespace excite::sim {
namespace {

// The order is a template parameter so the state lives in registers and the inner loop
// is unrolled.
template <std::size_t Order>
void run(const DiscreteTerm& d, const double* x, double* y, std::size_t count) {
  std::array<double, Order + 1> b{};
  std::array<double, Order + 1> a{};
  for (std::size_t i = 0; i <= Order; ++i) {
    b[i] = d.b[i];
    a[i] = d.a[i];
  }
  if constexpr (Order == 0) {
    for (std::size_t k = 0; k < count; ++k) y[k] += b[0] * x[k];
  } else {
    std::array<double, Order> s{};
    for (std::size_t k = 0; k < count; ++k) {
      const double xk = x[k];
      const double yk = b[0] * xk + s[0];
      for (std::size_t i = 0; i + 1 < Order; ++i) s[i] = b[i + 1] * xk - a[i + 1] * yk + s[i + 1];
      s[Order - 1] = b[Order] * xk - a[Order] * yk;
      y[k] += yk;
    }
  }
}

template <std::size_t... Orders>
void dispatch(std::size_t order, const DiscreteTerm& d, const double* x, double* y,
              std::size_t count, std::index_sequence<Orders...>) {
  static_cast<void>(((order == Orders ? (run<Orders>(d, x, y, count), true) : false) || ...));
}

}  // namespace

void tdf2_accumulate(const DiscreteTerm& d, const double* x, double* y, std::size_t count) {
  dispatch(static_cast<std::size_t>(d.order()), d, x, y, count,
           std::make_index_sequence<kMaxCoefficients>{});
}

}  // namespace excite::sim
