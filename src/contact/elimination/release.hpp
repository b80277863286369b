#pragma once
/// Releases (paper (46), (65)): a constraint holds while its normal force
/// f_N = g_s·n_{n+½} ≥ 0; how that force is read from the step's force
/// balance, and how far ahead a release is expected (releases located in
/// time, docs/theory.md, "Releases located in time").
#include <cstdint>
#include <vector>

#include "contact/constraint.hpp"

namespace conserve::contact {

/// A release counts as chatter if the slave was activated less than this
/// many steps before (history.csv `chatter`).
inline constexpr int kChatterWindow = 10;
/// A release counts as loaded if the slave's force at the end of the
/// previous step was above this fraction of the mean force then.
inline constexpr double kLoadedFraction = 0.01;

/// Releases located in time (release_step): where a pressing slave's force,
/// falling at its rate over the last two steps, would turn tensile within
/// this many full steps, the next step is shortened ...
inline constexpr double kReleaseHorizon = 4.0;
/// ... to this fraction of the longest step whose mean force would stay
/// ≥ 0, so that the steps shrink geometrically towards the lift-off, ...
inline constexpr double kReleaseApproach = 0.25;
/// ... but not below the step over which the force falls by this fraction
/// of the loaded threshold (kLoadedFraction of the mean force), nor below
/// 1/kReleaseShortest of the scenario's step, and to at most twice the
/// last step.
inline constexpr double kReleaseUnloading = 0.5;
inline constexpr double kReleaseShortest = 256.0;

/// f_N of each constraint from the full force balance g (its slave's rows:
/// the contact force), at each constraint's `normal`: g_s·n, or for a
/// slave holding two constraints the split of g_s along both normals
/// (their Gram system, solved by Cramer's rule). `slot` is scratch, one
/// entry per node, −1 on entry and on return.
template <int D>
std::vector<double> normal_forces(const std::vector<Constraint<D>>& active, const Eigen::VectorXd& g,
                                  std::vector<int>& slot);

/// Releases located in time: after step `step`, of length `last`, which
/// followed one of length `previous`, the longest next step (at most
/// `full`, the scenario's) for which no active constraint whose slave
/// pressed with more than kLoadedFraction of the mean force is expected to
/// let go more than about kReleaseUnloading of that threshold late. Its
/// force's rate of fall is taken from its force at the ends of the two
/// steps (Constraint::start_force, normal_force); slaves activated in step
/// `step` have none and are left out.
template <int D>
double release_step(const std::vector<Constraint<D>>& active, std::int64_t step, double full, double last,
                    double previous);

}  // namespace conserve::contact
