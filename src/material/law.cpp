#include "material/law.hpp"

#include <cmath>

namespace conserve::material {

Mat9 symmetric_product(const Mat3& A) {
  Mat9 T;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) T(i + 3 * j, k + 3 * l) = 0.5 * (A(i, k) * A(j, l) + A(i, l) * A(j, k));
  return T;
}

Mat9 dyad(const Mat3& A, const Mat3& B) {
  return Eigen::Map<const Eigen::Matrix<double, 9, 1>>(A.data()) *
         Eigen::Map<const Eigen::Matrix<double, 9, 1>>(B.data()).transpose();
}

namespace {

/// adj(A) = cof(A)ᵀ, so that A adj(A) = det(A) 1.
Mat3 adjugate(const Mat3& A) {
  Mat3 adj;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      adj(j, i) = A(i1, j1) * A(i2, j2) - A(i1, j2) * A(i2, j1);
    }
  return adj;
}

}  // namespace

double log_det_ratio(const Mat3& C, const Mat3& dC) {
  // tr(adj(C) ΔC) + tr(C adj(ΔC)) + det ΔC, the traces as sums of entries.
  const double change = adjugate(C).cwiseProduct(dC.transpose()).sum() +
                        C.cwiseProduct(adjugate(dC).transpose()).sum() + dC.determinant();
  return std::log1p(change / C.determinant());
}

}  // namespace conserve::material
