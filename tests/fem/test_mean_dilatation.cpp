// The mean-dilatation cell energy (fem/mean_dilatation.hpp), every law, 3D
// (4 points) and plane strain (3 points): its stress is W's gradient and
// the blocks ∂S_q/∂C_p are the stress's derivative (Taylor tests, order 2),
// with equal J at every point it is the law's stress, and the joint
// discrete gradient's work ½ Σ w_q S_q:ΔC_q is the step's ΔW to round-off
// (the mid-point stress misses it: the negative control).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "fem/mean_dilatation.hpp"
#include "material/law_cases.hpp"
#include "support/taylor.hpp"

namespace conserve::fem {
namespace {

using material::test::law_cases;
using material::test::make;
using material::test::random_F;

/// Every law at ν = 0.3 and 0.4999 (β = √(μ/κ) 0.68 and 0.014 in 3D).
std::vector<material::test::LawCase> cases() {
  auto all = law_cases(1.0e6, 0.3);
  for (auto& c : law_cases(1.0e6, 0.4999)) {
    all.push_back(c);
  }
  return all;
}

template <int Q>
constexpr int dim_of() {
  return Q == 4 ? 3 : 2;
}

/// Random C_q = F_qᵀF_q of strains up to `amount`, weights of a curved cell.
template <int Q>
DilatationCell<Q> random_cell(std::mt19937& rng, double amount) {
  constexpr int D = dim_of<Q>();
  DilatationCell<Q> c;
  c.dim = D;
  std::uniform_real_distribution<double> u(0.8, 1.2);
  for (int q = 0; q < Q; ++q) {
    const Mat<D> F = random_F<D>(rng, amount);
    c.C[static_cast<std::size_t>(q)] = material::embed_plane_strain<D>(Mat<D>(F.transpose() * F));
    c.w[static_cast<std::size_t>(q)] = 0.01 * u(rng);
  }
  return c;
}

/// The symmetric in-plane perturbation of the cell's C's along `d` (3 or
/// 6 entries a point).
template <int Q>
DilatationCell<Q> moved(const DilatationCell<Q>& c, const Eigen::VectorXd& d) {
  DilatationCell<Q> m = c;
  const int D = c.dim, per = D * (D + 1) / 2;
  for (int q = 0; q < Q; ++q) {
    int k = per * q;
    for (int i = 0; i < D; ++i)
      for (int j = i; j < D; ++j, ++k) {
        m.C[static_cast<std::size_t>(q)](i, j) += d(k);
        if (i != j) m.C[static_cast<std::size_t>(q)](j, i) += d(k);
      }
  }
  return m;
}

template <int Q>
void check_derivatives() {
  constexpr int D = dim_of<Q>();
  constexpr int n = Q * D * (D + 1) / 2;
  std::mt19937 rng(17);
  for (const auto& law_case : cases()) {
    const auto law = make(law_case);
    const DilatationCell<Q> cell = random_cell<Q>(rng, 0.3);
    const Eigen::VectorXd dir = test::random_direction(rng, n);
    const DilatationCell<Q> tip = moved<Q>(cell, dir);
    std::array<material::Mat9, Q * Q> dS;
    const std::array<Mat3, Q> S = mean_dilatation_stress<Q>(*law, cell, &dS);
    // δW = ½ Σ_q w_q S_q : δC_q.
    double slope = 0.0;
    Eigen::VectorXd dS_dir = Eigen::VectorXd::Zero(9 * Q);
    for (std::size_t q = 0; q < Q; ++q) {
      const Mat3 dC = tip.C[q] - cell.C[q];
      slope += 0.5 * cell.w[q] * S[q].cwiseProduct(dC).sum();
      for (std::size_t p = 0; p < Q; ++p) {
        const Mat3 dCp = tip.C[p] - cell.C[p];
        dS_dir.segment<9>(9 * static_cast<Eigen::Index>(q)) +=
            dS[q * Q + p] * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dCp.data());
      }
    }
    const auto energy = [&](const Eigen::VectorXd& y) {
      return Eigen::VectorXd::Constant(1, mean_dilatation_energy<Q>(*law, moved<Q>(cell, y)));
    };
    const auto stress = [&](const Eigen::VectorXd& y) {
      const std::array<Mat3, Q> s = mean_dilatation_stress<Q>(*law, moved<Q>(cell, y));
      Eigen::VectorXd v(9 * Q);
      for (int q = 0; q < Q; ++q) v.segment<9>(9 * q) = s[static_cast<std::size_t>(q)].reshaped();
      return v;
    };
    const test::TaylorOrder te =
        test::taylor_order(energy, Eigen::VectorXd::Zero(n), dir, Eigen::VectorXd::Constant(1, slope), 1e-2);
    const test::TaylorOrder ts = test::taylor_order(stress, Eigen::VectorXd::Zero(n), dir, dS_dir, 1e-2);
    std::printf("[ measured ] mean dilatation %dD %s: dW = S: %s; dS: %s\n", D, law_case.model.c_str(),
                test::describe(te).c_str(), test::describe(ts).c_str());
    test::expect_second_order(te, law_case.model + " energy");
    test::expect_second_order(ts, law_case.model + " stress");
  }
}

TEST(MeanDilatation, StressAndItsDerivative3d) { check_derivatives<4>(); }
TEST(MeanDilatation, StressAndItsDerivativePlaneStrain) { check_derivatives<3>(); }

// C_q of one J at every point: J̄ = J_q, C̄_q = C_q, and for Mooney–Rivlin
// (isochoric invariants: S_iso:C = 0, P_q = κ(J − 1)J the same at every
// point) S_q is the law's stress; for neo-Hookean (not split) it is not.
TEST(MeanDilatation, EqualDilatationsGiveTheSplitLawsStress) {
  std::mt19937 rng(3);
  for (const auto& law_case : law_cases()) {
    if (law_case.model != "mooney_rivlin" && law_case.model != "neo_hookean") continue;
    const auto law = make(law_case);
    DilatationCell<4> cell = random_cell<4>(rng, 0.3);
    for (auto& C : cell.C) C *= std::pow(1.3 / std::sqrt(C.determinant()), 2.0 / 3.0);  // J = 1.3
    const std::array<Mat3, 4> S = mean_dilatation_stress<4>(*law, cell);
    double worst = 0.0;
    for (std::size_t q = 0; q < 4; ++q) {
      const Mat3 expected = law->stress(cell.C[q]);
      worst = std::max(worst, (S[q] - expected).norm() / expected.norm());
    }
    std::printf("[ measured ] one J at every point, %s: |S_q - S(C_q)| / |S| <= %.1e\n", law_case.model.c_str(), worst);
    if (law_case.model == "mooney_rivlin")
      EXPECT_LT(worst, 1e-13);
    else
      EXPECT_GT(worst, 1e-3);  // the control: the same check can fail
  }
}

template <int Q>
void check_discrete_gradient() {
  constexpr int D = dim_of<Q>();
  std::mt19937 rng(23);
  for (const auto& law_case : cases()) {
    const auto law = make(law_case);
    for (int trial = 0; trial < 5; ++trial) {
      const DilatationCell<Q> start = random_cell<Q>(rng, 0.3);
      DilatationCell<Q> end = random_cell<Q>(rng, 0.3);
      end.w = start.w;
      const double dW = mean_dilatation_energy<Q>(*law, end) - mean_dilatation_energy<Q>(*law, start);
      DilatationCell<Q> mid = start;
      for (std::size_t q = 0; q < Q; ++q) mid.C[q] = 0.5 * (start.C[q] + end.C[q]);
      const std::array<Mat3, Q> S = mean_dilatation_discrete_gradient<Q>(*law, start, end);
      const std::array<Mat3, Q> S_mid = mean_dilatation_stress<Q>(*law, mid);
      double work = 0.0, work_mid = 0.0, W = 0.0;
      for (std::size_t q = 0; q < Q; ++q) {
        const Mat3 dC = end.C[q] - start.C[q];
        work += 0.5 * start.w[q] * S[q].cwiseProduct(dC).sum();
        work_mid += 0.5 * start.w[q] * S_mid[q].cwiseProduct(dC).sum();
        EXPECT_LT((S[q] - S[q].transpose()).norm(), 1e-14 * S[q].norm());
      }
      W = std::max(std::abs(mean_dilatation_energy<Q>(*law, end)), std::abs(mean_dilatation_energy<Q>(*law, start)));
      EXPECT_LT(std::abs(work - dW), 1e-12 * W) << law_case.model << " " << trial;
      if (trial == 0)
        std::printf("[ measured ] mean dilatation %dD %s: |work - dW| / W = %.1e, mid-point stress %.1e\n", D,
                    law_case.model.c_str(), std::abs(work - dW) / W, std::abs(work_mid - dW) / W);
      EXPECT_GT(std::abs(work_mid - dW), 1e-6 * W) << law_case.model << ": the control should miss";
    }
  }
}

// ∂S^algo/∂C_{n+1} by the Taylor test, every law, a step of 30 % strains.
template <int Q>
void check_discrete_gradient_derivative() {
  constexpr int D = dim_of<Q>();
  constexpr int n = Q * D * (D + 1) / 2;
  std::mt19937 rng(29);
  for (const auto& law_case : cases()) {
    const auto law = make(law_case);
    const DilatationCell<Q> start = random_cell<Q>(rng, 0.3);
    DilatationCell<Q> end = random_cell<Q>(rng, 0.3);
    end.w = start.w;
    const Eigen::VectorXd dir = test::random_direction(rng, n);
    const DilatationCell<Q> tip = moved<Q>(end, dir);
    std::array<material::Mat9, Q * Q> dS;
    mean_dilatation_discrete_gradient<Q>(*law, start, end, &dS);
    Eigen::VectorXd slope = Eigen::VectorXd::Zero(9 * Q);
    for (std::size_t q = 0; q < Q; ++q)
      for (std::size_t p = 0; p < Q; ++p) {
        const Mat3 dCp = tip.C[p] - end.C[p];
        slope.segment<9>(9 * static_cast<Eigen::Index>(q)) +=
            dS[q * Q + p] * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dCp.data());
      }
    const auto stress = [&](const Eigen::VectorXd& y) {
      const std::array<Mat3, Q> s = mean_dilatation_discrete_gradient<Q>(*law, start, moved<Q>(end, y));
      Eigen::VectorXd v(9 * Q);
      for (int q = 0; q < Q; ++q) v.segment<9>(9 * q) = s[static_cast<std::size_t>(q)].reshaped();
      return v;
    };
    const test::TaylorOrder t = test::taylor_order(stress, Eigen::VectorXd::Zero(n), dir, slope, 1e-2);
    std::printf("[ measured ] mean dilatation %dD %s: dS_algo/dC_n+1: %s\n", D, law_case.model.c_str(),
                test::describe(t).c_str());
    test::expect_second_order(t, law_case.model + " discrete gradient");
  }
}

TEST(MeanDilatation, DiscreteGradientDerivative3d) { check_discrete_gradient_derivative<4>(); }
TEST(MeanDilatation, DiscreteGradientDerivativePlaneStrain) { check_discrete_gradient_derivative<3>(); }

TEST(MeanDilatation, DiscreteGradientWorksTheEnergyChange3d) { check_discrete_gradient<4>(); }
TEST(MeanDilatation, DiscreteGradientWorksTheEnergyChangePlaneStrain) { check_discrete_gradient<3>(); }

/// As fem/discrete_gradient.hpp's (DiscreteGradient.NoNoiseAtSmallSteps*):
/// however small the step, the joint correction stays within 1e-13 M
/// (round-off of the stress, M = λ + 2μ) + 10 M |ΔC|². ΔW must come from
/// ΔC: C̄_{n+1} − C̄_n formed from two C̄'s carries ε|C|, and the
/// correction ε M |C| / |ΔC|.
template <int Q>
void check_no_noise_at_small_steps() {
  constexpr int D = dim_of<Q>();
  std::mt19937 rng(29);
  for (const auto& law_case : cases()) {
    const auto law = make(law_case);
    const material::Lame l = law->small_strain();
    const double M = l.lambda + 2.0 * l.mu;
    const DilatationCell<Q> a = random_cell<Q>(rng, 0.3), b = random_cell<Q>(rng, 0.3);
    double worst = 0.0;
    for (double s = 1e-3; s > 1e-12; s /= std::pow(10.0, 0.25)) {
      DilatationCell<Q> end = a, mid = a;
      double dCdC = 0.0;
      for (std::size_t q = 0; q < Q; ++q) {
        end.C[q] = a.C[q] + s * (b.C[q] - a.C[q]);
        if (D == 2) end.C[q](2, 2) = 1.0;
        mid.C[q] = 0.5 * (a.C[q] + end.C[q]);
        dCdC = std::max(dCdC, (end.C[q] - a.C[q]).squaredNorm());
      }
      const std::array<Mat3, Q> S = mean_dilatation_discrete_gradient<Q>(*law, a, end);
      const std::array<Mat3, Q> S_mid = mean_dilatation_stress<Q>(*law, mid);
      for (std::size_t q = 0; q < Q; ++q) {
        const double ratio = (S[q] - S_mid[q]).norm() / (M * (10.0 * dCdC + 1e-13));
        worst = std::max(worst, ratio);
        EXPECT_LT(ratio, 1.0) << law_case.model << " s = " << s;
      }
    }
    std::printf("[ measured ] mean dilatation %dD %s: |S_algo - S(C_mid)| / (M (10 |dC|^2 + 1e-13)) <= %.1e\n", D,
                law_case.model.c_str(), worst);
  }
}

TEST(MeanDilatation, NoNoiseAtSmallSteps3d) { check_no_noise_at_small_steps<4>(); }
TEST(MeanDilatation, NoNoiseAtSmallStepsPlaneStrain) { check_no_noise_at_small_steps<3>(); }

}  // namespace
}  // namespace conserve::fem
