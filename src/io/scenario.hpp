#pragma once
/// The scenario: everything a run needs, parsed once from a TOML file into
/// plain structs and validated. Every key is documented in docs/scenario.md.
#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/source_map.hpp"

namespace conserve::io {

/// Which algorithmic stress the time step uses.
enum class StressScheme {
  conserving,  ///< Simo–Tarnow: S_alg = ½(S(E_n) + S(E_{n+1})), with F_{n+½}
  midpoint,    ///< plain mid-point S(E(F_{n+½})): does NOT conserve energy (negative control)
};

enum class MassKind { consistent, lumped };
enum class ContactScheme { paper, persistent };
enum class PredictorKind { velocity, rigid };

/// [body.material]: a point law of material::law_catalog() and its
/// parameters (validated against the catalog), and the density.
struct MaterialSpec {
  std::string model = "svk";                 ///< the law's name in material::law_catalog()
  std::map<std::string, double> parameters;  ///< e.g. young [Pa], poisson; c10, c01, bulk [Pa]
  double density = 0.0;                      ///< reference density ρ0 [kg/m³], > 0
  /// The parameter `name`, 0 if the model has none of that name.
  [[nodiscard]] double parameter(const std::string& name) const {
    const auto it = parameters.find(name);
    return it == parameters.end() ? 0.0 : it->second;
  }
};

/// Where a body's mesh comes from: a file or a built-in generator.
struct MeshSpec {
  std::filesystem::path
      file;  ///< .msh 4.1 or .stl file, absolute (resolved against the scenario's folder); empty with a generator
  std::string group;      ///< cell physical group to take from the file; empty = all cells
  bool flip_normals = false;  ///< reverse a bare surface's facets (file only)
  bool reorder = false;       ///< renumber a file's nodes in reverse Cuthill–McKee order (file only)
  std::string generator;  ///< generator name (mesh/generators.hpp); empty with a file
  std::map<std::string, double> parameters;  ///< generator parameters, validated against the catalog
};

struct BodySpec {
  std::string name;
  MeshSpec mesh;
  MaterialSpec material;
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();  ///< shifts the reference configuration [m]
  /// Turns the mesh about the origin of its coordinates, before `translate`
  /// (2D: the upper 2 × 2 block).
  Eigen::Matrix3d rotate = Eigen::Matrix3d::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   ///< uniform initial velocity [m/s]
  /// Rigid rotation about the body's centre of mass [rad/s]; in 2D only z.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  /// Initial deformation gradient F0 applied about the body's centroid c:
  /// u0(X) = (F0 - I)(X - c). Identity = undeformed. 2D uses the upper 2×2.
  Eigen::Matrix3d initial_deformation = Eigen::Matrix3d::Identity();
  double thickness = 1.0;  ///< out-of-plane thickness in 2D (plane strain) [m]
  /// A quadratic cell's volume change at each point, or the cell's mean
  /// (fem/mean_dilatation.hpp: nearly incompressible rubber).
  bool mean_dilatation = false;
  /// All degrees of freedom prescribed (model/prescribed.hpp): the body
  /// translates at velocity · c_v(t) and turns at angular_velocity · c_ω(t)
  /// about `center` (its material is not used). Only a rigid body may be a
  /// bare surface (no cells), made by the generators `square` and `segment`
  /// or read from a .msh surface or line mesh or an STL file.
  bool rigid = false;
  /// A rigid body whose motion contact, gravity and its initial velocity
  /// and spin decide (time/free_bodies.hpp) instead of a prescription: it
  /// needs a density and cells; no curves, no `center` (its centre of mass).
  bool free = false;
  /// Rigid bodies: the point it turns about [m]; none: its bounding box's centre.
  std::optional<Eigen::Vector3d> center;
  std::string velocity_curve;          ///< rigid bodies: [[curve]] scaling velocity; empty: none
  std::string angular_velocity_curve;  ///< rigid bodies: [[curve]] scaling angular_velocity; empty: none
};

/// A surface load (model/loads.hpp): a nominal traction or a follower pressure.
struct LoadSpec {
  std::string body;
  std::string group = "boundary";
  bool pressure = false;                               ///< a follower pressure, else a traction
  Eigen::Vector3d traction = Eigen::Vector3d::Zero();  ///< [Pa]
  double pressure_value = 0.0;                         ///< [Pa]
  std::string curve;                                   ///< [[curve]] scaling it; empty: none
};

/// A load curve: piecewise linear through `points` (t strictly
/// increasing), constant beyond the first and the last.
struct CurveSpec {
  std::string name;
  std::vector<std::pair<double, double>> points;  ///< (t [s], value)
};

/// How a penalty force is evaluated in the step.
enum class PenaltyForce { conserving, midpoint };

enum class ContactKind {
  frictionless,  ///< paper §4.3.2: conserves E, L and J
  stick,         ///< paper §4.3.1: full stick, conserves E and L
  coulomb,       ///< Coulomb friction μ: stick inside the cone, slip on it; L, J kept, E + dissipated kept
};

/// A node-to-segment contact pair: the slave surface's nodes against the
/// master surface's facets. Choose the finer mesh as the slave.
struct ContactSpec {
  std::string slave_body;
  std::string slave_group = "boundary";  ///< facet group; "boundary" = the whole boundary
  std::string master_body;
  std::string master_group = "boundary";
  ContactKind kind = ContactKind::frictionless;
  double friction = 0.0;  ///< Coulomb coefficient μ (kind coulomb)
  /// Far-side cut-off: a facet counts while the slave is less than
  /// depth_factor × (its longest edge) behind it.
  double depth_factor = 0.5;
  /// 1: the slave's nodes are held out of the master's facets; 2: also the
  /// master's nodes out of the slave's facets (both deformable).
  int passes = 1;
  /// [general_contact]'s pairs of two deformable bodies: the surfaces are
  /// swapped when the slave's is the coarser (simulation::make_contact_pairs).
  bool finer_slave = false;
  std::string method = "elimination";  ///< constraint method (contact/method.hpp); the same for every pair
  double penalty = 0.0;                ///< penalty stiffness ε [Pa/m]; 0: automatic
  PenaltyForce penalty_force = PenaltyForce::conserving;
};

/// Active-set control (docs/theory.md, "The step with contact").
struct ActiveSetSpec {
  int max_passes = 30;  ///< solves of one step before giving up on a changing active set
  /// `persistent` (default): after each step the relative velocity of the
  /// active slaves is set to zero and its energy given back (contact/
  /// persistent_velocity.hpp); `paper`: the mid-point velocity (19) only.
  ContactScheme scheme = ContactScheme::persistent;
  /// End a step early at an impact, so that a slave is activated with a
  /// gap of at most gap_tolerance × (its slave facets' longest edge).
  /// With the paper's velocity every activation bounces the slave off and
  /// each return is another split: the paper's scheme turns it off.
  bool locate_impacts = true;
  double gap_tolerance = 1e-3;
  /// The largest gap (× the facet size) of an impact that follows the
  /// first of its pair (contact spreading, a slave back after its release):
  /// such impacts are taken together (contact::ImpactLocation).
  double cluster_tolerance = 0.1;
  /// Shorten the steps ahead of a predicted lift-off, so that a slave lets
  /// go with almost no force left (contact::ActiveSet::release_step).
  bool locate_releases = false;
};

/// Prescribed displacement on a node set: u_i(t) = value_i c(t) + rate_i t
/// for each listed component i (c = 1 without a curve).
struct BoundarySpec {
  std::string body;                                 ///< body name
  std::string group;                                ///< facet group of the body's mesh, or "all" (every node)
  std::vector<int> components;                      ///< prescribed components, 0 = x, 1 = y, 2 = z
  Eigen::Vector3d value = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d rate = Eigen::Vector3d::Zero();   ///< [m/s]
  std::string curve;                                ///< [[curve]] scaling value; empty: none
};

struct TimeSpec {
  double step = 0.0;  ///< Δt [s], > 0
  double end = 0.0;   ///< end time [s], ≥ step
  StressScheme scheme = StressScheme::conserving;
  MassKind mass = MassKind::consistent;
  /// Floor of the cutback: a step that fails is retried with Δt halved
  /// while Δt/2 ≥ min_step [s]; ≤ step (0 in the file: step/1024).
  double min_step = 0.0;
};

struct NewtonSpec {
  int max_iterations = 20;
  /// converged when |r| ≤ residual_tolerance · (reference force of the
  /// step), or at |r|'s round-off floor (solver/newton.hpp)
  double residual_tolerance = 1e-12;
  /// Newton's start: rigid (each free body's rigid motion) or velocity
  /// (u_n + Δt V_n); both add ½Δt² g (time/predictor.hpp)
  PredictorKind predictor = PredictorKind::rigid;
};

/// [solver]: the linear solver of the Newton systems (solver/linear_solver.hpp).
struct SolverSpec {
  std::string method = "krylov";           ///< krylov | direct
  std::string preconditioner = "auto";     ///< auto | ilu | gamg (krylov)
  int gamg_from = 2147483647;              ///< auto: GAMG from this many unknowns on (default: never)
  bool graph_partition = true;             ///< partition = "graph" (else "ranges"): simulation/rank_numbering.hpp
  int max_linear_iterations = 200;
  double forcing_max = 0.1;                ///< Eisenstat–Walker's largest relative linear tolerance
  bool modified_newton = true;             ///< keep the tangent while convergence is fast
  std::string petsc_options;
  int threads = 0;  ///< assembly threads; 0: automatic (assembly::ThreadGovernor)
};

struct OutputSpec {
  std::filesystem::path directory = "out";  ///< relative to the working directory
  int vtu_every = 10;          ///< write a VTU every N steps (0: none; the first and last are always written if > 0)
  bool compress = true;        ///< VTU arrays zlib-compressed
  bool single_precision = true;  ///< VTU fields as Float32
  int progress_every = 0;      ///< 0: a progress line about once a second
  bool contact_state = false;  ///< also write the slaves' contact state (gap, normal, facet) with each VTU
  int checkpoint_every = 0;    ///< write checkpoints/ckpt_NNNNNN.bin every N steps (0: none)
  int checkpoint_keep = 3;     ///< keep the newest N periodic checkpoints (0: all)
};

struct Scenario {
  std::filesystem::path file;  ///< where it was read from (for messages)
  std::string text;            ///< the file's bytes as parsed (copied to the output as scenario.toml)
  SourceMap sources;           ///< where each key was given: errors found later name its line
  std::string title;
  int dimension = 3;  ///< 2 (plane strain) or 3
  TimeSpec time;
  NewtonSpec newton;
  SolverSpec solver;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< [m/s²]
  std::string gravity_curve;                          ///< [[curve]] scaling gravity; empty: none
  std::vector<LoadSpec> loads;
  std::vector<BodySpec> bodies;
  std::vector<BoundarySpec> boundaries;
  std::vector<ContactSpec> contacts;
  std::vector<CurveSpec> curves;
  ActiveSetSpec active_set;
  OutputSpec output;
};

/// Reads and validates a scenario file. Throws InputError
/// "FILE:LINE: key: what is wrong (what was expected)".
///
/// `overrides` (`conserve run --set`) replace or add keys of the file's
/// tables before it is validated, each "SECTION.KEY=VALUE" (nested tables
/// by more dots, e.g. `active_set.scheme=persistent`, `time.end=0.1`).
/// VALUE is read as a TOML value if it is one (`true`, `1e-3`, `[0, 0,
/// -9.81]`, `"text"`), else as a string. A missing table is created;
/// entries of arrays of tables (`[[body]]`) are not reachable. With
/// overrides, `Scenario::text` is the effective scenario, written out as
/// TOML under a comment naming the file and the overrides. A malformed
/// override, or a value the key does not accept, throws InputError
/// "--set KEY: ...".
Scenario read_scenario(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

/// Same from text; `file` is used for messages and to resolve mesh paths.
Scenario parse_scenario(std::string_view text, const std::filesystem::path& file,
                        const std::vector<std::string>& overrides = {});

}  // namespace conserve::io
