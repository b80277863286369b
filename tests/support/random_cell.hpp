#pragma once
/// Random, well-shaped cells and deformations for kernel tests.
#include <random>

#include "fem/simplex.hpp"

namespace conserve::test {

/// A positively oriented reference simplex: the unit simplex, randomly
/// perturbed, scaled by `size`.
template <int D>
fem::NodeMatrix<D> random_reference_cell(std::mt19937& rng, double size = 1.0) {
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  fem::NodeMatrix<D> X = fem::NodeMatrix<D>::Zero();
  for (int a = 1; a <= D; ++a) X(a - 1, a) = 1.0;
  for (int a = 0; a <= D; ++a)
    for (int i = 0; i < D; ++i) X(i, a) += jitter(rng);
  return size * X;
}

/// A large deformation of X: rotation-like mixing plus stretch, and noise
/// of relative amplitude `noise`.
template <int D>
fem::NodeMatrix<D> random_deformed(std::mt19937& rng, const fem::NodeMatrix<D>& X, double noise) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat<D> F = Mat<D>::Identity();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) F(i, j) += 0.3 * u(rng);
  fem::NodeMatrix<D> x = F * X;
  for (int a = 0; a <= D; ++a)
    for (int i = 0; i < D; ++i) x(i, a) += noise * u(rng);
  return x;
}

}  // namespace conserve::test
