// Gonzalez's discrete gradient (fem/discrete_gradient.hpp), per law, 3D and
// plane strain: the identity ½ S_algo : ΔC = ρ0Ψ(C_{n+1}) − ρ0Ψ(C_n) to
// round-off on random pairs, including pairs whose ΔC is swept across the
// fallback on both sides; ∂S_algo/∂C_{n+1} by the Taylor test;
// for SVK (quadratic) it is the Simo–Tarnow stress.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "fem/discrete_gradient.hpp"
#include "material/law_cases.hpp"
#include "support/taylor.hpp"

namespace conserve::fem {
namespace {

using material::test::LawCase;
constexpr double kEps = std::numeric_limits<double>::epsilon();

/// |½ S_algo:ΔC − ΔΨ| (ΔΨ from Law::energy_change) and the scale it is
/// round-off of: (|S| + M|C|)|ΔC|, M the small-strain P-wave modulus.
struct Identity {
  double error = 0.0, scale = 0.0;
  bool mid_point = false;
};

double modulus(const material::Law& law) {
  const material::Lame l = law.small_strain();
  return l.lambda + 2.0 * l.mu;
}

Identity identity(const material::Law& law, const Mat3& C_n, const Mat3& C_np1) {
  const AlgorithmicStress a = discrete_gradient(law, C_n, C_np1, false);
  const Mat3 dC = C_np1 - C_n;
  const double work = 0.5 * a.S.cwiseProduct(dC).sum();
  return {std::abs(work - law.energy_change(C_n, dC)),
          (a.S.norm() + modulus(law) * (0.5 * (C_n + C_np1)).norm()) * dC.norm(), a.mid_point};
}

template <int D>
void check_identity_on_random_pairs(const LawCase& c) {
  const auto law = material::test::make(c);
  std::mt19937 rng(21);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const Mat3 C_n = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const Mat3 C_np1 = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const Identity id = identity(*law, C_n, C_np1);
    ASSERT_GT(id.scale, 1e3);  // non-zero guard
    worst = std::max(worst, id.error / id.scale);
  }
  std::printf("[ measured ] %s %dD: |½ S_algo:ΔC − ΔΨ| / scale, worst of 200 random pairs: %.1e\n", c.model.c_str(), D,
              worst);
  EXPECT_LT(worst, 1e3 * kEps) << c.model;
}

TEST(DiscreteGradient, EnergyIdentityOnRandomPairs3d) {
  for (const auto& c : material::test::law_cases()) check_identity_on_random_pairs<3>(c);
}
TEST(DiscreteGradient, EnergyIdentityOnRandomPairs2d) {
  for (const auto& c : material::test::law_cases()) check_identity_on_random_pairs<2>(c);
}

/// ΔC = s·(C_b − C_a) swept over s = 1 to 1e-12 from a strained C_a: the
/// fallback is taken for small s and not for large, and the identity holds
/// to round-off on both sides of the switch.
template <int D>
void check_identity_across_the_fallback(const LawCase& c) {
  const auto law = material::test::make(c);
  std::mt19937 rng(22);
  int fallbacks = 0, corrected = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C_a = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const Mat3 C_b = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    bool last = false;
    for (double s = 1.0; s > 1e-14; s /= std::pow(10.0, 0.125)) {
      const Identity id = identity(*law, C_a, C_a + s * (C_b - C_a));
      (id.mid_point ? fallbacks : corrected)++;
      if (id.mid_point != last && s < 1.0) {  // around the switch, both sides
        std::printf("[ measured ] %s %dD: the mid-point fallback from |ΔC|/|C| = %.1e down\n", c.model.c_str(), D,
                    s * (C_b - C_a).norm() / C_a.norm());
      }
      last = id.mid_point;
      worst = std::max(worst, id.error / id.scale);
    }
  }
  EXPECT_LT(worst, 64.0 * kEps) << c.model;
  EXPECT_GT(fallbacks, 0) << c.model;
  EXPECT_GT(corrected, 0) << c.model;
}

// (SVK is left out: its r is zero up to round-off at any step, and the
// program never gives it the discrete gradient.)
TEST(DiscreteGradient, EnergyIdentityAcrossTheFallback3d) {
  for (const auto& c : material::test::law_cases())
    if (c.model != "svk") check_identity_across_the_fallback<3>(c);
}
TEST(DiscreteGradient, EnergyIdentityAcrossTheFallback2d) {
  for (const auto& c : material::test::law_cases())
    if (c.model != "svk") check_identity_across_the_fallback<2>(c);
}

/// ∂S_algo/∂C_{n+1} by the Taylor test of S_algo(C_n, ·) at C_{n+1} along
/// random symmetric directions (a remainder of order 2, support/taylor.hpp).
/// For SVK, whose energy is quadratic, S_algo is the mid-point stress,
/// linear in C_{n+1}: its remainder has no order but is round-off at every
/// step, where a wrong derivative would leave h |δ(dS) dC|.
template <int D>
void check_derivative(const LawCase& c) {
  const auto law = material::test::make(c);
  std::mt19937 rng(23);
  test::TaylorOrder worst;
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C_n = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const Mat3 C_np1 = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const AlgorithmicStress a = discrete_gradient(*law, C_n, C_np1, true);
    ASSERT_GT(a.dS.norm(), 1e4);  // non-zero guard
    const Mat3 dC = material::test::random_symmetric<D>(rng);
    auto stress = [&](const Eigen::VectorXd& C) {
      return Eigen::VectorXd(discrete_gradient(*law, C_n, C.reshaped(3, 3), false).S.reshaped());
    };
    const test::TaylorOrder t = test::taylor_order(stress, C_np1.reshaped(), dC.reshaped(), a.dS * dC.reshaped(), 1e-2);
    const std::string what = c.model + " " + std::to_string(D) + "D, trial " + std::to_string(trial);
    if (c.model == "svk") {
      test::expect_exact(t, what);
    } else {
      test::expect_second_order(t, what);
    }
    worst = trial == 0 ? t : test::worse(t, worst);
  }
  std::printf("[ measured ] %s %dD, ∂S_algo/∂C_{n+1} at 5 random pairs, the worst: %s\n", c.model.c_str(), D,
              test::describe(worst).c_str());
}

TEST(DiscreteGradient, DerivativeMatchesDifferences3d) {
  for (const auto& c : material::test::law_cases()) check_derivative<3>(c);
}
TEST(DiscreteGradient, DerivativeMatchesDifferences2d) {
  for (const auto& c : material::test::law_cases()) check_derivative<2>(c);
}

/// The correction 2r ΔC/(ΔC:ΔC) is O(|ΔC|²) and never noise: however small
/// the step, S_algo − S(C_mid) stays within 1e-13 M (round-off of the
/// stress) + 10 M |ΔC|² (the quadrature error of the mid-point rule).
template <int D>
void check_no_noise_at_small_steps(const LawCase& c) {
  const auto law = material::test::make(c);
  std::mt19937 rng(25);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 C_a = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    const Mat3 C_b = material::test::right_cauchy_green<D>(material::test::random_F<D>(rng, 0.3));
    for (double s = 1e-3; s > 1e-14; s /= std::pow(10.0, 0.125)) {
      const Mat3 C_np1 = C_a + s * (C_b - C_a), dC = C_np1 - C_a;
      const Mat3 correction = discrete_gradient(*law, C_a, C_np1, false).S - law->stress(0.5 * (C_a + C_np1));
      EXPECT_LT(correction.norm(), modulus(*law) * (10.0 * dC.squaredNorm() + 1e-13)) << c.model << " s = " << s;
    }
  }
}

TEST(DiscreteGradient, NoNoiseAtSmallSteps3d) {
  for (const auto& c : material::test::law_cases())
    if (c.model != "svk") check_no_noise_at_small_steps<3>(c);
}
TEST(DiscreteGradient, NoNoiseAtSmallSteps2d) {
  for (const auto& c : material::test::law_cases())
    if (c.model != "svk") check_no_noise_at_small_steps<2>(c);
}

/// Law::energy_change of a tiny step is ½ S(C_mid):ΔC up to O(|ΔC|³) and
/// round-off ε M |ΔC|; the difference of two energies misses it by ε M |C|
/// (the negative control), which is why the discrete gradient uses it.
TEST(DiscreteGradient, EnergyChangeIsAccurateForTinySteps) {
  std::mt19937 rng(26);
  for (const auto& c : material::test::law_cases()) {  // SVK too: the mean dilatation's joint gradient uses it
    const auto law = material::test::make(c);
    const Mat3 C_n = material::test::right_cauchy_green<3>(material::test::random_F<3>(rng, 0.3));
    const Mat3 C_np1 = C_n + 1e-10 * material::test::right_cauchy_green<3>(material::test::random_F<3>(rng, 0.3));
    const Mat3 dC = C_np1 - C_n;
    const double mid = 0.5 * law->stress(0.5 * (C_n + C_np1)).cwiseProduct(dC).sum();
    const double round_off = kEps * modulus(*law) * dC.norm();
    ASSERT_GT(std::abs(mid), 1e3 * round_off);  // non-zero guard
    EXPECT_LT(std::abs(law->energy_change(C_n, dC) - mid), 16.0 * round_off) << c.model;
    EXPECT_GT(std::abs(law->energy(C_np1) - law->energy(C_n) - mid), 16.0 * round_off) << c.model << ": the control";
  }
}

TEST(DiscreteGradient, ForSvkItIsTheSimoTarnowStress) {
  const auto svk = material::test::make(material::test::law_cases()[0]);
  std::mt19937 rng(24);
  const Mat3 C_n = material::test::right_cauchy_green<3>(material::test::random_F<3>(rng, 0.3));
  const Mat3 C_np1 = material::test::right_cauchy_green<3>(material::test::random_F<3>(rng, 0.3));
  const Mat3 simo_tarnow = 0.5 * (svk->stress(C_n) + svk->stress(C_np1));
  EXPECT_LT((discrete_gradient(*svk, C_n, C_np1, false).S - simo_tarnow).norm(), 1e-12 * simo_tarnow.norm());
}

}  // namespace
}  // namespace conserve::fem
