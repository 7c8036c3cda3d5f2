// SPDX-License-Identifier: MIT
#include "sim/lti/difference_equation.hpp"

#include <algorithm>
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

// The n = G terms padded to one order: the coefficients beyond a term's own order are zero
// (DiscreteTerm keeps them so), and its padded states stay ±0, which leave every sum as it was.
template <std::size_t G, std::size_t Order>
void run_side_by_side(const DiscreteTerm* const* d, const double* gains, const double* const* x,
                      double* y, std::size_t count) {
  std::array<std::array<double, Order + 1>, G> b{};
  std::array<std::array<double, Order + 1>, G> a{};
  for (std::size_t j = 0; j < G; ++j) {
    for (std::size_t i = 0; i <= Order; ++i) {
      b[j][i] = d[j]->b[i];
      a[j][i] = d[j]->a[i];
    }
  }
  std::array<std::array<double, Order>, G> s{};
  for (std::size_t k = 0; k < count; ++k) {
    double sum = y[k];
    for (std::size_t j = 0; j < G; ++j) {
      const double xk = x[j][k];
      if constexpr (Order == 0) {
        sum += gains[j] * (b[j][0] * xk);
      } else {
        const double yk = b[j][0] * xk + s[j][0];
        for (std::size_t i = 0; i + 1 < Order; ++i)
          s[j][i] = b[j][i + 1] * xk - a[j][i + 1] * yk + s[j][i + 1];
        s[j][Order - 1] = b[j][Order] * xk - a[j][Order] * yk;
        sum += gains[j] * yk;
      }
    }
    y[k] = sum;
  }
}

template <std::size_t G, std::size_t... Orders>
void dispatch_side_by_side(std::size_t order, const DiscreteTerm* const* d, const double* gains,
                           const double* const* x, double* y, std::size_t count,
                           std::index_sequence<Orders...>) {
  static_cast<void>(
      ((order == Orders ? (run_side_by_side<G, Orders>(d, gains, x, y, count), true) : false) ||
       ...));
}

template <std::size_t... Orders>
void dispatch(std::size_t order, const DiscreteTerm& d, const double* x, double* y,
              std::size_t count, std::index_sequence<Orders...>) {
  static_cast<void>(((order == Orders ? (run<Orders>(d, x, y, count), true) : false) || ...));
}

template <std::size_t... Gs>
void dispatch_count(std::size_t n, std::size_t order, const DiscreteTerm* const* d,
                    const double* gains, const double* const* x, double* y, std::size_t count,
                    std::index_sequence<Gs...>) {
  static_cast<void>(
      ((n == Gs + 1 ? (dispatch_side_by_side<Gs + 1>(order, d, gains, x, y, count,
                                                     std::make_index_sequence<kMaxCoefficients>{}),
                       true)
                    : false) ||
       ...));
}

}  // namespace

void tdf2_accumulate_sum(std::span<const DiscreteTerm* const> terms, std::span<const double> gains,
                         std::span<const double* const> x, double* y, std::size_t count) {
  std::size_t order = 0;
  for (const DiscreteTerm* d : terms) order = std::max(order, static_cast<std::size_t>(d->order()));
  dispatch_count(terms.size(), order, terms.data(), gains.data(), x.data(), y, count,
                 std::make_index_sequence<kMaxSideBySide>{});
}

void tdf2_accumulate(const DiscreteTerm& d, const double* x, double* y, std::size_t count) {
  dispatch(static_cast<std::size_t>(d.order()), d, x, y, count,
           std::make_index_sequence<kMaxCoefficients>{});
}

}  // namespace excite::sim
