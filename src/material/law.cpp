#include "material/law.hpp"

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

}  // namespace conserve::material
