#pragma once
/// The Taylor test of a derivative: with the exact derivative J of f at x,
/// the remainder e(h) = |f(x + h d) − f(x) − h J d| falls as h², so that
/// log2 e(h)/e(h/2) ≈ 2, whereas a wrong or missing term leaves a remainder
/// of order h (order ≈ 1). The order does not depend on the machine's
/// rounding while e(h) stays well above it, unlike a bound on a difference
/// quotient at one step size (which a CPU with other rounding exceeded).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace conserve::test {

struct TaylorOrder {
  std::vector<double> remainders;  ///< e(h_k), h_k = h0 / 2^k
  /// The order at the smallest steps: the mean of log2 e(h_k)/e(h_k+1)
  /// over the last three pairs whose remainders are both above the
  /// round-off floor (larger steps may cross a kink of f: a contact that
  /// opens, a projection that changes facet), NaN if none is.
  double order = std::numeric_limits<double>::quiet_NaN();
  int pairs = 0;       ///< the pairs above the floor
  double slope = 0.0;  ///< |J d|: the derivative along d (non-zero guard)
  double floor = 0.0;  ///< the round-off floor the remainders were judged against
};

/// e(h_k) for h_k = h0 / 2^k, k = 0 … halvings. `f(v)` returns a vector;
/// `Jd` is the derivative's action on `d`. The round-off floor is
/// `floor_factor` · ε · the largest |f| seen (ε = 2.2e-16): remainders below
/// it are rounding, not Taylor's.
template <class F>
TaylorOrder taylor_order(F&& f, const Eigen::VectorXd& x, const Eigen::VectorXd& d, const Eigen::VectorXd& Jd,
                         double h0, int halvings = 12, double floor_factor = 1e4) {
  TaylorOrder t;
  t.slope = Jd.norm();
  const Eigen::VectorXd f0 = f(x);
  double largest = f0.norm();
  for (int k = 0; k <= halvings; ++k) {
    const double h = h0 / std::pow(2.0, k);
    const Eigen::VectorXd fh = f(Eigen::VectorXd(x + h * d));
    largest = std::max(largest, fh.norm());
    t.remainders.push_back((fh - f0 - h * Jd).norm());
  }
  t.floor = floor_factor * std::numeric_limits<double>::epsilon() * largest;
  std::vector<double> orders;
  for (std::size_t k = 0; k + 1 < t.remainders.size() && t.remainders[k + 1] > t.floor; ++k)
    orders.push_back(std::log2(t.remainders[k] / t.remainders[k + 1]));
  t.pairs = static_cast<int>(orders.size());
  if (orders.empty()) return t;
  const std::size_t first = orders.size() > 3 ? orders.size() - 3 : 0;
  t.order = 0.0;
  for (std::size_t k = first; k < orders.size(); ++k) t.order += orders[k] / static_cast<double>(orders.size() - first);
  return t;
}

/// "order 2.00 (e 1.2e-3 … 3.1e-6, 4 pairs)" for the test's output.
inline std::string describe(const TaylorOrder& t) {
  char text[160];
  std::snprintf(text, sizeof text, "order %.2f (remainders %.1e … %.1e over %d pairs, |J d| %.1e)", t.order,
                t.remainders.front(), t.remainders[static_cast<std::size_t>(std::max(t.pairs, 0))], t.pairs, t.slope);
  return text;
}

/// The assertions of a Taylor test: a non-zero derivative, at least
/// `min_pairs` pairs above round-off, and an order of about 2 (a missing
/// term gives 1).
inline void expect_second_order(const TaylorOrder& t, const std::string& what, int min_pairs = 3) {
  EXPECT_GT(t.slope, 0.0) << what << ": the derivative along the direction is zero";
  EXPECT_GE(t.pairs, min_pairs) << what << ": " << describe(t);
  EXPECT_GT(t.order, 1.8) << what << ": " << describe(t);
}

}  // namespace conserve::test
