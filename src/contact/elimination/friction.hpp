#pragma once
/// Coulomb friction's stick and slip (docs/theory.md, "Coulomb friction"):
/// a slave of a Coulomb pair sticks (the stick kind's constraint, frozen
/// where it started the step) while its force lies inside the cone
/// |P g_s| ≤ μ f_N, and slips (the frictionless kind's constraint with a
/// friction force μ f_N against its objective slip,
/// zero_work::friction_direction) otherwise. The active set asks these
/// after each converged solve; a change solves the step again.
#include "contact/constraint.hpp"

namespace conserve::contact {

/// A sticking slave slips once its tangential force exceeds the cone by
/// more than this fraction of μ f_N (round-off at the cone's edge does not
/// switch it).
inline constexpr double kConeTolerance = 1e-6;
/// The slip ε below which a slipping slave's friction direction is
/// regularized, as a fraction of its facet size (Constraint::slip_scale):
/// a slave that would stop within a step comes to |Δs| of order ε with a
/// force inside the cone, and sticks.
inline constexpr double kSlipScale = 1e-6;
/// A slipping slave sticks when its slip over a step is below this
/// fraction of ε, its friction then below a tenth of μ f_N: well inside
/// the cone. Between that and ε the regularized force holds it, creeping
/// by less than ε a step; a slave whose stick force would leave the cone
/// (a corner of a block on an incline, where the force concentrates)
/// stays there instead of switching back and forth.
inline constexpr double kStickSlip = 0.1;

/// Whether sticking constraint c, whose slave's force over the step is
/// `force` (g_s) with normal part f_N = c.normal_force along c.normal,
/// leaves the cone of friction μ: f_N > 0 and |g_s − f_N n| >
/// μ f_N (1 + kConeTolerance).
template <int D>
bool leaves_cone(const Constraint<D>& c, const Vec<D>& force, double mu);

/// The slipping constraint a sticking one becomes: the same facet and
/// held gap, friction μ, its direction regularized below kSlipScale ×
/// `facet_size`.
template <int D>
Constraint<D> to_slip(Constraint<D> c, double mu, double facet_size);

/// The sticking constraint a slipping one of pair `pr` becomes: frozen at
/// the point of its facet where its slave started the step (positions
/// x_n), at the height it had there, so that it holds what the slave had
/// (no work).
template <int D>
Constraint<D> to_stick(Constraint<D> c, const ContactPair<D>& pr, const Positions<D>& x_n);

/// A slipping slave's step x_n → x_np1: its objective slip |Δs| [m] and
/// the friction's dissipation μ f_N |Δs|²/√(|Δs|² + ε²) [J], f_N its
/// constraint's normal force.
struct FrictionStep {
  double slip = 0.0;
  double dissipated = 0.0;
};
template <int D>
FrictionStep friction_step(const Constraint<D>& c, const Positions<D>& x_n, const Positions<D>& x_np1);

}  // namespace conserve::contact
