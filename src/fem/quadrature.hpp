#pragma once
/// Symmetric quadrature rules with positive weights on the reference
/// simplex of dimension K (weights sum to its measure 1/K!), exact for
/// polynomials of the stated degree. The digits were solved here from the
/// moment equations to 40 digits; tests/fem/test_lagrange.cpp checks the
/// exactness on every monomial.
///   K = 1: Gauss–Legendre on [0, 1], 2 points (degree 3), 3 points (5).
///   K = 2: 1 point (1), 3 points (2), 6 points (4; Dunavant 1985).
///   K = 3: 1 point (1), 4 points (2), 14 points (5; Walkington 2000).
#include <array>
#include <cmath>

#include "core/types.hpp"

namespace conserve::fem {

template <int K, int Q>
struct Quadrature {
  static constexpr int kPoints = Q;
  std::array<Vec<K>, Q> points;
  std::array<double, Q> weights;
};

namespace detail {

/// Adds the points of the orbit of barycentric λ = (r, …, r, s, …) under
/// the vertex permutations: S31/S22 for tetrahedra, S21 for triangles.
template <int K, int Q>
void add_point(Quadrature<K, Q>& q, int& at, const Eigen::Matrix<double, K + 1, 1>& lambda, double w) {
  q.points[static_cast<std::size_t>(at)] = lambda.template tail<K>();
  q.weights[static_cast<std::size_t>(at)] = w;
  ++at;
}

}  // namespace detail

/// The rule of degree at least `degree` (1 ≤ degree ≤ 5 for K = 1, 3; ≤ 4
/// for K = 2) with the fewest points in the list above.
template <int K, int Degree>
constexpr int rule_points() {
  if constexpr (K == 1) return Degree <= 3 ? 2 : 3;
  if constexpr (K == 2) return Degree <= 1 ? 1 : Degree == 2 ? 3 : 6;
  if constexpr (K == 3) return Degree <= 1 ? 1 : Degree == 2 ? 4 : 14;
}

template <int K, int Degree>
Quadrature<K, rule_points<K, Degree>()> quadrature() {
  constexpr int Q = rule_points<K, Degree>();
  static_assert((K == 2 && Degree <= 4) || (K != 2 && Degree <= 5), "no rule of that degree");
  Quadrature<K, Q> q;
  using Lambda = Eigen::Matrix<double, K + 1, 1>;
  int at = 0;
  // All permutations of (r, …, r, s): one point per position of s.
  const auto orbit_1 = [&](double r, double s, double w) {
    for (int i = 0; i <= K; ++i) {
      Lambda l = Lambda::Constant(r);
      l(i) = s;
      detail::add_point<K, Q>(q, at, l, w);
    }
  };
  if constexpr (K == 1) {
    if constexpr (Q == 2) {
      const double d = 0.5 / std::sqrt(3.0);
      detail::add_point<K, Q>(q, at, Lambda(0.5 + d, 0.5 - d), 0.5);
      detail::add_point<K, Q>(q, at, Lambda(0.5 - d, 0.5 + d), 0.5);
    } else {
      const double d = 0.5 * std::sqrt(0.6);
      detail::add_point<K, Q>(q, at, Lambda(0.5 + d, 0.5 - d), 5.0 / 18.0);
      detail::add_point<K, Q>(q, at, Lambda(0.5, 0.5), 8.0 / 18.0);
      detail::add_point<K, Q>(q, at, Lambda(0.5 - d, 0.5 + d), 5.0 / 18.0);
    }
  } else if constexpr (Q == 1) {
    detail::add_point<K, Q>(q, at, Lambda::Constant(1.0 / (K + 1)), K == 2 ? 0.5 : 1.0 / 6.0);
  } else if constexpr (K == 2 && Q == 3) {
    orbit_1(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0);
  } else if constexpr (K == 2 && Q == 6) {
    constexpr double a = 0.44594849091596488632, b = 0.09157621350977074346;
    orbit_1(a, 1.0 - 2.0 * a, 0.11169079483900573285);
    orbit_1(b, 1.0 - 2.0 * b, 0.054975871827660933819);
  } else if constexpr (K == 3 && Q == 4) {
    const double a = (5.0 - std::sqrt(5.0)) / 20.0;
    orbit_1(a, 1.0 - 3.0 * a, 1.0 / 24.0);
  } else if constexpr (K == 3 && Q == 14) {
    constexpr double a1 = 0.092735250310891226402, a2 = 0.3108859192633006098, b = 0.45449629587435035051;
    orbit_1(a1, 1.0 - 3.0 * a1, 0.012248840519393658257);
    orbit_1(a2, 1.0 - 3.0 * a2, 0.0187813209530026418);
    constexpr std::array<std::array<int, 2>, 6> pairs{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
    for (const auto& [i, j] : pairs) {
      Lambda l = Lambda::Constant(0.5 - b);
      l(i) = l(j) = b;
      detail::add_point<K, Q>(q, at, l, 0.007091003462846911073);
    }
  }
  return q;
}

}  // namespace conserve::fem
