#include "fem/discrete_gradient.hpp"

#include <cmath>
#include <limits>

namespace conserve::fem {

AlgorithmicStress discrete_gradient(const material::Law& law, const Mat3& C_n, const Mat3& C_np1,
                                    bool with_derivative) {
  const Mat3 C_mid = 0.5 * (C_n + C_np1), dC = C_np1 - C_n;
  AlgorithmicStress a;
  a.S = law.stress(C_mid);
  const double r = law.energy_change(C_n, dC) - 0.5 * a.S.cwiseProduct(dC).sum();
  const double dCdC = dC.squaredNorm();
  const material::Lame lame = law.small_strain();
  const double noise = kRoundOffMultiple * std::numeric_limits<double>::epsilon() *
                       (a.S.norm() + (lame.lambda + 2.0 * lame.mu) * C_mid.norm()) * std::sqrt(dCdC);
  a.mid_point = !(dCdC > 0.0) || !(std::abs(r) > noise);
  if (!a.mid_point) a.S += (2.0 * r / dCdC) * dC;
  if (!with_derivative) return a;
  const material::Mat9 C4 = law.tangent(C_mid);
  a.dS = 0.25 * C4;
  if (a.mid_point) return a;
  using Vec9 = Eigen::Matrix<double, 9, 1>;
  const Eigen::Map<const Vec9> d(dC.data());
  const Vec9 C4d = C4 * d;
  const Mat3 w = 0.5 * (law.stress(C_np1) - law.stress(C_mid)) - 0.125 * Eigen::Map<const Mat3>(C4d.data());
  const double k = 2.0 / dCdC;
  static const material::Mat9 identity = material::symmetric_product(Mat3::Identity());
  a.dS += k * (d * Eigen::Map<const Vec9>(w.data()).transpose() + r * identity -
               (2.0 * r / dCdC) * d * d.transpose());
  return a;
}

}  // namespace conserve::fem
