#pragma once
/// Fixed-size algebra types shared by all layers.
#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace conserve {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Global sparse matrices: compressed columns, int indices (UMFPACK "di").
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

}  // namespace conserve
