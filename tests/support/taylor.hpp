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
#include <random>
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

/// "order 2.00 (remainders 1.2e-3 … 3.1e-6 over 4 pairs, |J d| 5.0e+1)" for
/// the test's output; with no pair above round-off (an affine f), the
/// largest remainder against the floor.
inline std::string describe(const TaylorOrder& t) {
  char text[160];
  if (t.pairs == 0) {
    std::snprintf(text, sizeof text, "no order: remainders at most %.1e, round-off floor %.1e, |J d| %.1e",
                  *std::max_element(t.remainders.begin(), t.remainders.end()), t.floor, t.slope);
  } else {
    std::snprintf(text, sizeof text, "order %.2f (remainders %.1e … %.1e over %d pairs, |J d| %.1e)", t.order,
                  t.remainders.front(), t.remainders[static_cast<std::size_t>(t.pairs)], t.pairs, t.slope);
  }
  return text;
}

/// A direction with `n` entries uniform in [−1, 1].
inline Eigen::VectorXd random_direction(std::mt19937& rng, Eigen::Index n) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d[i] = unit(rng);
  return d;
}

/// The assertions of a Taylor test: a non-zero derivative, at least
/// `min_pairs` pairs above round-off, and an order of about 2 (a missing
/// term gives 1).
inline void expect_second_order(const TaylorOrder& t, const std::string& what, int min_pairs = 3) {
  EXPECT_GT(t.slope, 0.0) << what << ": the derivative along the direction is zero";
  EXPECT_GE(t.pairs, min_pairs) << what << ": " << describe(t);
  EXPECT_GT(t.order, 1.8) << what << ": " << describe(t);
}

/// The largest remainder relative to the round-off floor (at most 1 for an
/// affine f with its exact derivative).
inline double largest_remainder(const TaylorOrder& t) {
  return *std::max_element(t.remainders.begin(), t.remainders.end()) / t.floor;
}

/// The worse of two tests of one derivative (for the output): the lower
/// order, or with no order either (an affine f), the larger remainder
/// against the floor.
inline const TaylorOrder& worse(const TaylorOrder& a, const TaylorOrder& b) {
  if (a.pairs == 0 && b.pairs == 0) return largest_remainder(a) >= largest_remainder(b) ? a : b;
  return b.order < a.order ? b : a;
}

/// The assertions of a Taylor test of an affine f (a constant derivative:
/// the inertia's, SVK's stress in C, a facet's edge vectors), whose
/// remainder is round-off at every step and has no order: a non-zero
/// derivative and every remainder within the floor, where a wrong J would
/// leave h |δJ d|, order 1.
inline void expect_exact(const TaylorOrder& t, const std::string& what) {
  EXPECT_GT(t.slope, 0.0) << what << ": the derivative along the direction is zero";
  EXPECT_LE(largest_remainder(t), 1.0) << what << ": " << describe(t);
}

}  // namespace conserve::test
