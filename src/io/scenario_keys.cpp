/// The declared scenario keys (the single source for validation and docs).
#include "io/scenario_keys.hpp"

#include <stdexcept>

namespace conserve::io {
namespace {

constexpr Bound above(double v) { return {v, false}; }
constexpr Bound at_least(double v) { return {v, true}; }
constexpr Bound below(double v) { return {v, false}; }
constexpr Bound at_most(double v) { return {v, true}; }

SectionSpec top_level() {
  return {.name = "",
          .doc = "Top level of the file.",
          .keys = {
              {.name = "title", .type = KeyType::string, .doc = "free text shown in the output"},
              {.name = "dimension",
               .type = KeyType::integer,
               .default_value = "3",
               .min = at_least(2),
               .max = at_most(3),
               .doc = "2 (plane strain, triangles) or 3 (tetrahedra)"},
              {.name = "time", .type = KeyType::table, .required = true, .doc = "time stepping, see [time]"},
              {.name = "newton", .type = KeyType::table, .doc = "Newton solver, see [newton]"},
              {.name = "solver", .type = KeyType::table, .doc = "linear solver, see [solver]"},
              {.name = "loads", .type = KeyType::table, .doc = "body forces, see [loads]"},
              {.name = "output", .type = KeyType::table, .doc = "output files, see [output]"},
              {.name = "body",
               .type = KeyType::table_array,
               .required = true,
               .doc = "the bodies, one [[body]] table each (at least one)"},
              {.name = "boundary",
               .type = KeyType::table_array,
               .doc = "prescribed displacements, one [[boundary]] table each"},
              {.name = "contact", .type = KeyType::table_array, .doc = "contact pairs, one [[contact]] table each"},
              {.name = "load", .type = KeyType::table_array, .doc = "surface loads, one [[load]] table each"},
              {.name = "curve",
               .type = KeyType::table_array,
               .doc = "load curves, one [[curve]] table each, named by rigid bodies, [[boundary]], [[load]] and "
                      "[loads]"},
              {.name = "active_set", .type = KeyType::table, .doc = "contact active-set control, see [active_set]"},
              {.name = "general_contact",
               .type = KeyType::table,
               .doc = "contact between every pair of bodies and of each body with itself, see [general_contact]"},
          }};
}

SectionSpec time_section() {
  return {
      .name = "time",
      .doc = "Time stepping.",
      .keys = {
          {.name = "step",
           .type = KeyType::number,
           .required = true,
           .unit = "s",
           .min = above(0),
           .doc = "time step Δt"},
          {.name = "end",
           .type = KeyType::number,
           .required = true,
           .unit = "s",
           .doc = "end time; must be ≥ step, and end / step ≤ 2^53"},
          {.name = "scheme",
           .type = KeyType::choice,
           .default_value = "conserving",
           .choices = {"conserving", "midpoint"},
           .doc = "algorithmic stress: `conserving` (energy–momentum conserving, Simo–Tarnow) "
                  "or `midpoint` (plain mid-point rule; does not conserve energy, a negative control)"},
          {.name = "mass",
           .type = KeyType::choice,
           .default_value = "consistent",
           .choices = {"consistent", "lumped"},
           .doc = "mass matrix"},
          {.name = "min_step",
           .type = KeyType::number,
           .default_value = "0",
           .unit = "s",
           .min = at_least(0),
           .doc = "floor of the cutback (0: step/1024): a step whose Newton iteration fails is retried from the same "
                  "state with "
                  "Δt halved, while Δt/2 ≥ min_step (Δt doubles back, up to `step`, after 4 good steps); below the "
                  "floor the run stops (exit code 3) with the last converged state saved; must be ≤ `step`"},
      }};
}

SectionSpec newton_section() {
  return {.name = "newton",
          .doc = "Newton iteration of each step.",
          .keys = {
              {.name = "max_iterations",
               .type = KeyType::integer,
               .default_value = "20",
               .min = at_least(1),
               .doc = "iterations before the step fails"},
              {.name = "residual_tolerance",
               .type = KeyType::number,
               .default_value = "1e-12",
               .min = above(0),
               .doc = "converged when |r| ≤ tolerance · (reference force of the step: the largest of the inertia, "
                      "load and elastic force norms at its start), or when |r| is at its round-off floor (ε times "
                      "the forces it sums) and that floor is at most 1e-6 of the reference force (else the step fails: the model is too stiff for double precision at this Δt); a small "
                      "increment alone never ends the iteration"},
              {.name = "predictor",
               .type = KeyType::choice,
               .default_value = "rigid",
               .choices = {"rigid", "velocity"},
               .doc = "where each step's iteration starts: `rigid`, each free body moved by the rigid part of its "
                      "velocity (its centre-of-mass velocity and spin, fitted with the lumped masses; bodies with a "
                      "prescribed component keep their velocity), or `velocity`, u_n + Δt V_n; both add ½Δt² g. "
                      "The solution does not depend on it; the iterations do: at steps far above a body's "
                      "vibration periods the step all but reverses the vibration, which `velocity` carries forward"},
          },
          .retired = {{"increment_tolerance",
                       "removed: Newton converges on the residual only (see residual_tolerance); delete the key"},
                      {"reuse_factorization", "moved: it is [solver] modified_newton now"}}};
}

SectionSpec solver_section() {
  return {.name = "solver",
          .doc = "Linear solver of the Newton systems. The default, GMRES with ILU(0) or GAMG, solves each system "
                 "only as accurately as Newton needs (Eisenstat–Walker); the step's convergence is judged on the "
                 "nonlinear residual alone, so conservation does not depend on the choice.",
          .keys = {
              {.name = "method",
               .type = KeyType::choice,
               .default_value = "krylov",
               .choices = {"krylov", "direct"},
               .doc = "`krylov` (PETSc GMRES, right-preconditioned, inexact Newton) or `direct` (UMFPACK LU, exact "
                      "solves, the reference; memory grows fast beyond ~200k unknowns in 3D)"},
              {.name = "preconditioner",
               .type = KeyType::choice,
               .default_value = "auto",
               .choices = {"auto", "ilu", "gamg"},
               .doc = "krylov only: `ilu` (block ILU(0) on the nodes' D × D blocks, natural order, rebuilt per matrix), `gamg` (algebraic multigrid "
                      "with the rigid-body modes, interpolation kept while the pattern stays) or `auto` (ilu below "
                      "gamg_from unknowns, gamg from there on)"},
              {.name = "gamg_from",
               .type = KeyType::integer,
               .default_value = "2147483647",
               .min = at_least(1),
               .doc = "preconditioner = \"auto\": unknowns from which gamg is used (by default never: ilu was "
                      "2.4–3.6× faster per Newton iteration at 2.93M unknowns on 1 and 2 ranks, "
                      "bench/results/scaling_model.md)"},
              {.name = "partition",
               .type = KeyType::choice,
               .default_value = "graph",
               .choices = {"graph", "ranges"},
               .doc = "on several MPI ranks: `graph` numbers the nodes of a body that ranks share (generated, or "
                      "read with `reorder`) part by part of a PT-Scotch partition, so each rank holds a compact "
                      "piece with few ghost nodes (a checkpoint then restarts on the same rank count only); "
                      "`ranges` keeps one numbering for every rank count and cuts it into contiguous ranges"},
              {.name = "max_linear_iterations",
               .type = KeyType::integer,
               .default_value = "200",
               .min = at_least(1),
               .doc = "GMRES iterations per solve; a solve that reaches them near its tolerance returns its best "
                      "iterate (Newton judges the residual), one that stagnates far from it is redone by the LU"},
              {.name = "forcing_max",
               .type = KeyType::number,
               .default_value = "0.1",
               .min = above(0),
               .max = below(1),
               .doc = "krylov: the loosest relative tolerance of a linear solve (Eisenstat–Walker η_max); later "
                      "iterations tighten it as Newton converges"},
              {.name = "modified_newton",
               .type = KeyType::boolean,
               .default_value = "true",
               .doc = "keep a tangent (and its factorization or preconditioner) across iterations and steps while "
                      "each iteration reduces the residual 4× and, at that rate, reaches the tolerance with "
                      "iterations to spare; one that reduces it less than 100× while 3 more iterations are "
                      "projected is replaced at the next iterate, assembled in the same pass as its residual; "
                      "same conservation (false: full Newton, a tangent per iteration); a step that fails with kept "
                      "tangents is tried again with a fresh one per iteration before its Δt is halved"},
              {.name = "petsc_options",
               .type = KeyType::string,
               .default_value = "",
               .doc = "krylov: extra PETSc options, e.g. \"-ksp_monitor\" (process-wide)"},
              {.name = "threads",
               .type = KeyType::integer,
               .default_value = "0",
               .min = at_least(0),
               .doc = "assembly threads; 0: automatic, as many as the cores other processes leave free, "
                      "re-measured every second (or OMP_NUM_THREADS if set); results are the same bits for any "
                      "count"},
          }};
}

SectionSpec loads_section() {
  return {.name = "loads",
          .doc = "Body forces.",
          .keys = {
              {.name = "gravity",
               .type = KeyType::vector,
               .default_value = "zeros",
               .unit = "m/s²",
               .doc = "gravitational acceleration, `dimension` numbers"},
              {.name = "gravity_curve",
               .type = KeyType::string,
               .doc = "a [[curve]] scaling `gravity` in time; its work is then counted in history.csv's "
                      "`load_work` instead of `potential`"},
          }};
}

SectionSpec load_section() {
  return {.name = "load",
          .doc = "A surface load on a facet group of a deformable body; repeat [[load]] for each. Its work "
                 "is in the energy balance: a constant `traction` has a potential (in `potential`), a "
                 "`pressure` or a load with a curve does work counted in `load_work` (history.csv's "
                 "`total` is E − load_work, which the scheme conserves).",
          .keys = {
              {.name = "body", .type = KeyType::string, .required = true, .doc = "name of a deformable [[body]]"},
              {.name = "group",
               .type = KeyType::string,
               .default_value = "boundary",
               .doc = "a facet group of the body's mesh on its boundary, or `boundary` (all of it)"},
              {.name = "traction",
               .type = KeyType::vector,
               .unit = "Pa",
               .doc = "nominal traction: force per reference area, fixed in direction, `dimension` numbers; "
                      "exactly one of `traction` and `pressure`"},
              {.name = "pressure",
               .type = KeyType::number,
               .unit = "Pa",
               .doc = "follower pressure along the current inward normal (positive pushes into the body); "
                      "exactly one of `traction` and `pressure`"},
              {.name = "curve",
               .type = KeyType::string,
               .doc = "a [[curve]] scaling the load in time (taken at each step's mid-point time)"},
          }};
}

SectionSpec output_section() {
  return {.name = "output",
          .doc = "Output files.",
          .keys = {
              {.name = "directory",
               .type = KeyType::string,
               .default_value = "out",
               .doc = "output folder, relative to the working directory"},
              {.name = "vtu_every",
               .type = KeyType::integer,
               .default_value = "10",
               .min = at_least(0),
               .doc = "write a VTU file every N steps (0: none; if > 0 the first and last step are always written)"},
              {.name = "compress",
               .type = KeyType::boolean,
               .default_value = "true",
               .doc = "VTU arrays in zlib-compressed blocks (VTK's `vtkZLibDataCompressor`, read by ParaView, VTK "
                      "and meshio); `false`: raw binary"},
              {.name = "precision",
               .type = KeyType::choice,
               .default_value = "single",
               .choices = {"single", "double"},
               .doc = "VTU point and cell fields as Float32 (7 significant digits, as FEBio's and Abaqus' result "
                      "files) or Float64 (about 1.8× the size compressed); the points stay Float64, and "
                      "history.csv, summary.json and the checkpoints keep every digit either way"},
              {.name = "progress_every",
               .type = KeyType::integer,
               .default_value = "0",
               .min = at_least(0),
               .doc = "print a progress line every N steps (0: about once a second)"},
              {.name = "contact_state",
               .type = KeyType::boolean,
               .default_value = "false",
               .doc = "with each VTU, also write every slave node's contact state (gap, master normal and facet, "
                      "ξ) to vtu/contact_NNNNNN_pairK.vtu, for debugging contact in ParaView"},
              {.name = "checkpoint_every",
               .type = KeyType::integer,
               .default_value = "0",
               .min = at_least(0),
               .doc = "write a checkpoint every N steps to checkpoints/ckpt_NNNNNN.bin (0: none), to continue "
                      "with `conserve run SCENARIO --restart FILE`"},
              {.name = "checkpoint_keep",
               .type = KeyType::integer,
               .default_value = "3",
               .min = at_least(0),
               .doc = "keep only the newest N periodic checkpoints, deleting older ones as new ones are written "
                      "(0: keep all)"},
          }};
}

SectionSpec body_section() {
  return {.name = "body",
          .doc = "One body; repeat [[body]] for each.",
          .keys = {
              {.name = "name",
               .type = KeyType::string,
               .required = true,
               .doc = "unique name (used by [[boundary]], [[contact]] and in the output); a name is non-empty, "
                      "has no `,`, `\"`, `:` or control characters and no leading or trailing spaces (history.csv's "
                      "header and the \"body:group\" syntax carry it)"},
              {.name = "rigid",
               .type = KeyType::boolean,
               .default_value = "false",
               .doc = "all degrees of freedom prescribed: the body moves rigidly, translating at `velocity` and "
                      "turning at `angular_velocity` about `center`, each rate scaled by its curve if given "
                      "(docs/user-guide.md, \"Rigid bodies\"); no `initial_deformation` or [[boundary]]; "
                      "`material` optional; its mesh may be a bare surface (`square`, `segment`, a .msh surface "
                      "or line mesh, an STL file)"},
              {.name = "free",
               .type = KeyType::boolean,
               .default_value = "false",
               .doc = "with `rigid = true`: a free rigid body, whose motion contact, gravity and its initial "
                      "`velocity` and `angular_velocity` decide (energy–momentum conserving, docs/theory.md, "
                      "\"Free rigid bodies\"); it needs a [body.material] `density` and a mesh with cells (its "
                      "mass, centre of mass and inertia come from them); no curves or `center`; it is the master "
                      "of its contact pairs"},
              {.name = "translate",
               .type = KeyType::vector,
               .default_value = "zeros",
               .unit = "m",
               .doc = "shift of the mesh's reference configuration, `dimension` numbers"},
              {.name = "velocity",
               .type = KeyType::vector,
               .default_value = "zeros",
               .unit = "m/s",
               .doc = "uniform initial velocity (the constant velocity of a rigid body), `dimension` numbers"},
              {.name = "angular_velocity",
               .type = KeyType::angular_velocity,
               .default_value = "zeros",
               .unit = "rad/s",
               .doc = "initial rigid rotation about the centre of mass (a rigid body: its rotation rate about "
                      "`center`, the axis fixed): 3 numbers in 3D, one number (about z) in 2D"},
              {.name = "center",
               .type = KeyType::vector,
               .default_value = "the centre of the body's bounding box",
               .unit = "m",
               .doc = "rigid bodies: the point the body turns about (it moves with the body's translation), "
                      "`dimension` numbers"},
              {.name = "velocity_curve",
               .type = KeyType::string,
               .doc = "rigid bodies: a [[curve]] c(t) scaling `velocity`: v(t) = velocity · c(t), so that the "
                      "body can start, stop and reverse"},
              {.name = "angular_velocity_curve",
               .type = KeyType::string,
               .doc = "rigid bodies: a [[curve]] scaling `angular_velocity`: ω(t) = angular_velocity · c(t)"},
              {.name = "initial_deformation",
               .type = KeyType::matrix,
               .default_value = "identity",
               .doc = "initial deformation gradient F0 (rows), applied about the centroid c: "
                      "u0(X) = (F0 − I)(X − c); det F0 > 0"},
              {.name = "thickness",
               .type = KeyType::number,
               .default_value = "1",
               .unit = "m",
               .min = above(0),
               .doc = "out-of-plane thickness; 2D only (an error in 3D)"},
              {.name = "dilatation",
               .type = KeyType::choice,
               .default_value = "points",
               .choices = {"points", "mean"},
               .doc = "how a cell's volume change enters its energy: at each quadrature point, or `mean`, the "
                      "cell's mean J at every point, with a share √(μ/κ) of the point's own (F-bar: nearly incompressible "
                      "materials do not lock; docs/theory.md); "
                      "`mean` needs `[body.mesh] order = 2` and a deformable body"},
              {.name = "material",
               .type = KeyType::table,
               .doc = "material, see [body.material]; required unless `rigid = true` (then it is still validated "
                      "if given; without it the rigid body is massless)"},
              {.name = "mesh", .type = KeyType::table, .required = true, .doc = "mesh, see [body.mesh]"},
              {.name = "rotate",
               .type = KeyType::table,
               .doc = "turns the mesh about the origin of its coordinates, before `translate`: see "
                      "[body.rotate]"},
          }};
}

SectionSpec rotate_section() {
  return {.name = "body.rotate",
          .doc = "A rotation of the body's mesh about the origin of its coordinates, applied before `translate` "
                 "(e.g. `rotate = {axis = [0, 1, 0], degrees = 30}`): exactly one of `degrees` (with `axis` in "
                 "3D; about z in 2D) or `matrix`.",
          .keys = {
              {.name = "axis",
               .type = KeyType::vector,
               .doc = "3D: the axis to turn about (any length but zero), right-handed"},
              {.name = "degrees",
               .type = KeyType::number,
               .unit = "degrees",
               .doc = "the angle, counter-clockwise about `axis` (2D: about z)"},
              {.name = "matrix",
               .type = KeyType::matrix,
               .doc = "the rotation matrix (rows): orthogonal with determinant 1, to 1e-9"},
          }};
}

SectionSpec material_section() {
  return {.name = "body.material",
          .doc = "Material of the body: a point law (`model`) with its parameters, listed under \"Material "
                 "models\" below, and the density. A rigid body's may be its `density` alone.",
          .keys = {
              {.name = "model",
               .type = KeyType::string,
               .default_value = "svk",
               .doc = "the point law: svk, neo_hookean or mooney_rivlin (\"Material models\" below); only its "
                      "parameters are accepted"},
              {.name = "density",
               .type = KeyType::number,
               .required = true,
               .unit = "kg/m³",
               .min = above(0),
               .doc = "reference density ρ0"},
          },
          .open = true};
}

SectionSpec mesh_section() {
  return {.name = "body.mesh",
          .doc =
              "The body's mesh: exactly one of `file` or `generator`. With `generator`, `order` sets the "
              "element order and every other key is a parameter of that generator (a number, see the "
              "generator list below).",
          .keys =
              {
                  {.name = "file",
                   .type = KeyType::string,
                   .doc = "Gmsh .msh 4.1 file (linear or quadratic cells, e.g. `gmsh -order 2`) or STL file (`.stl`, "
                          "ASCII or binary, 3D), relative to the "
                          "scenario file's folder; must exist. A rigid body's may be a bare surface: a .msh file "
                          "without cells but with 3-node triangles (3D) or 2-node lines (2D), or an STL file; facet "
                          "groups `surface` (all facets) and the file's physical groups; its facets must be "
                          "consistently oriented, and their normals (right-hand rule; (t_y, −t_x) in 2D) point to "
                          "the slaves' side (`conserve check` states which way)"},
                  {.name = "group",
                   .type = KeyType::string,
                   .default_value = "",
                   .doc = "cell physical group to take from the file (empty: all cells); only with `file`, not "
                          "with a bare surface"},
                  {.name = "flip_normals",
                   .type = KeyType::boolean,
                   .default_value = "false",
                   .doc = "reverse every facet of a bare surface read from `file`, so that its normals point "
                          "the other way"},
                  {.name = "reorder",
                   .type = KeyType::boolean,
                   .default_value = "false",
                   .doc = "renumber the nodes of the mesh read from `file` in reverse Cuthill–McKee order, as a "
                          "generated mesh's: the assembly and ILU(0) run faster on a file whose numbering "
                          "scatters a cell's nodes (Gmsh's Delaunay: about 2× a Newton iteration on a 100k-unknown ball, bench/results/large_models.md); outputs and "
                          "messages then number nodes and cells in that order, not the file's"},
                  {.name = "generator",
                   .type = KeyType::string,
                   .doc = "name of a built-in mesh generator; its `dim` must equal `dimension`"},
                  {.name = "order",
                   .type = KeyType::integer,
                   .default_value = "1",
                   .min = Bound{1, true},
                   .max = Bound{2, true},
                   .doc = "element order of a generated mesh: 1 (3-node triangles, 4-node tetrahedra) or 2 "
                          "(6-node triangles, 10-node tetrahedra, their boundary midside nodes on the true curved "
                          "surface); only with `generator` (a file's element types give its order: Gmsh types 2 "
                          "and 4, or 9 and 11); a bare surface (`square`, `segment`) is order 1 only"},
              },
          .open = true};
}

SectionSpec boundary_section() {
  return {.name = "boundary",
          .doc =
              "Prescribed displacement u_i(t) = value_i + rate_i · t of the listed components "
              "on a node set; repeat [[boundary]] for each.",
          .keys = {
              {.name = "body", .type = KeyType::string, .required = true, .doc = "name of a [[body]]"},
              {.name = "group",
               .type = KeyType::string,
               .required = true,
               .doc = "`all` (every node of the body) or a facet group of its mesh "
                      "(checked when the model is built); a name as for [[body]] `name`"},
              {.name = "components",
               .type = KeyType::components,
               .default_value = "all",
               .doc = "prescribed components, e.g. [\"x\", \"z\"]; default: all of the dimension"},
              {.name = "value",
               .type = KeyType::vector,
               .default_value = "zeros",
               .unit = "m",
               .doc = "displacement at t = 0, `dimension` numbers (entries of unlisted components are ignored)"},
              {.name = "rate",
               .type = KeyType::vector,
               .default_value = "zeros",
               .unit = "m/s",
               .doc = "displacement rate, `dimension` numbers"},
              {.name = "curve",
               .type = KeyType::string,
               .doc = "a [[curve]] c(t) scaling `value`: u_i(t) = value_i · c(t) + rate_i · t"},
          }};
}

SectionSpec curve_section() {
  return {.name = "curve",
          .doc = "A load curve: piecewise linear through its points, constant beyond the first and the last; "
                 "repeat [[curve]] for each. A curve scales a rigid body's rates, a [[boundary]]'s value or "
                 "a load.",
          .keys = {
              {.name = "name",
               .type = KeyType::string,
               .required = true,
               .doc = "unique name, used by the keys that take a curve; a name as for [[body]] `name`"},
              {.name = "points",
               .type = KeyType::points,
               .required = true,
               .doc = "[[t, value], …]: at least two points, t [s] strictly increasing"},
          }};
}

SectionSpec contact_section() {
  return {.name = "contact",
          .doc =
              "A node-to-segment contact pair: the nodes of the slave surface against the facets of the master "
              "surface; repeat [[contact]] for each pair. A surface is written \"body\" (its whole boundary) "
              "or \"body:group\" (a facet group of its mesh, checked when the model is built).",
          .keys = {
              {.name = "slave",
               .type = KeyType::string,
               .required = true,
               .doc = "slave surface, \"body\" or \"body:group\" (group default `boundary`; the group a name as "
                      "for [[body]] `name`); choose the finer mesh; a rigid body cannot be the slave"},
              {.name = "master",
               .type = KeyType::string,
               .required = true,
               .doc = "master surface, \"body\" or \"body:group\" (as for `slave`); the slave surface itself for "
                      "self-contact (a node is not held on the facets at it and its neighbours)"},
              {.name = "kind",
               .type = KeyType::choice,
               .required = true,
               .choices = {"frictionless", "stick", "coulomb"},
               .doc = "`frictionless` (conserves energy, linear and angular momentum), `stick` (full stick "
                      "friction; conserves energy, linear and angular momentum) or `coulomb` (Coulomb friction "
                      "with coefficient `friction`: a slave sticks while its tangential force is inside μ × its "
                      "normal force and slips against it otherwise; conserves linear and angular momentum and "
                      "energy + `dissipated` (history.csv); every method)"},
              {.name = "friction",
               .type = KeyType::number,
               .default_value = "0",
               .min = at_least(0),
               .doc = "kind = \"coulomb\" (and required there): the Coulomb friction coefficient μ"},
              {.name = "depth_factor",
               .type = KeyType::number,
               .default_value = "0.5",
               .min = above(0),
               .doc = "far-side cut-off: a facet counts while the slave node is less than depth_factor × "
                      "(the facet's longest edge) behind it"},
              {.name = "passes",
               .type = KeyType::integer,
               .default_value = "1",
               .min = at_least(1),
               .doc = "1: the slave surface's nodes are held out of the master's facets; 2: the master's nodes "
                      "out of the slave's facets too (two-pass contact: neither side penetrates the other; kind "
                      "`frictionless` only; against a rigid master each of its nodes is held by a node of the "
                      "slave's facet)"},
              {.name = "method",
               .type = KeyType::choice,
               .default_value = "elimination",
               .choices = {"elimination", "lagrange", "penalty"},
               .doc = "constraint method, the same for every pair (later pairs take the first pair's): "
                      "`elimination` (the slave's unknowns eliminated, no penetration), `lagrange` (the same "
                      "constraints held by multipliers, extra unknowns) or `penalty` (a penalty potential; "
                      "the slave penetrates by about its pressure / `penalty`)"},
              {.name = "penalty",
               .type = KeyType::number,
               .default_value = "0",
               .unit = "Pa/m",
               .min = at_least(0),
               .doc = "method = \"penalty\": stiffness ε per unit area of the slave node's share of its "
                      "surface; 0 = automatic, the smaller of E/h over the pair's deformable sides (E the "
                      "body's Young's modulus, h the median facet size of its surface)"},
              {.name = "penalty_force",
               .type = KeyType::choice,
               .default_value = "conserving",
               .choices = {"conserving", "midpoint"},
               .doc = "method = \"penalty\", the same for every pair: `conserving` (discrete gradient: "
                      "energy incl. the springs', L and J conserved) or `midpoint` (the force at the mid-point "
                      "configuration; does not conserve energy, a negative control)"},
          }};
}

SectionSpec general_contact_section() {
  return {.name = "general_contact",
          .doc = "Contact between all bodies: its presence pairs every two bodies (both deformable: `passes` if "
                 "frictionless, else one; "
                 "one rigid: the deformable one's nodes against the rigid one's facets; two rigid: none) and each "
                 "deformable body with itself (self-contact), their whole boundaries, instead of [[contact]] "
                 "tables (the two are not combined).",
          .keys = {
              {.name = "kind",
               .type = KeyType::choice,
               .default_value = "frictionless",
               .choices = {"frictionless", "stick", "coulomb"},
               .doc = "the kind of every pair, as [[contact]] `kind`"},
              {.name = "friction",
               .type = KeyType::number,
               .default_value = "0",
               .min = at_least(0),
               .doc = "kind = \"coulomb\": the Coulomb friction coefficient μ"},
              {.name = "method",
               .type = KeyType::choice,
               .default_value = "elimination",
               .choices = {"elimination", "lagrange", "penalty"},
               .doc = "constraint method, as [[contact]] `method`"},
              {.name = "exclude",
               .type = KeyType::names,
               .doc = "bodies left out of contact"},
              {.name = "passes",
               .type = KeyType::integer,
               .default_value = "2",
               .min = at_least(1),
               .max = at_most(2),
               .doc = "passes of the frictionless pairs of two deformable bodies, as [[contact]] `passes`: 2 holds "
                      "both sides' nodes; 1 the finer surface's alone (the earlier body's if alike), for flat faces "
                      "of unlike meshes pressed on each other, which two passes over-constrain (docs/theory.md)"},
              {.name = "self",
               .type = KeyType::boolean,
               .default_value = "true",
               .doc = "self-contact of each deformable body"},
              {.name = "pair",
               .type = KeyType::table_array,
               .doc = "settings of one pair of bodies, one [[general_contact.pair]] table each"},
          }};
}

SectionSpec general_contact_pair_section() {
  return {.name = "general_contact.pair",
          .doc = "The kind (and friction) or the passes of one pair of bodies under [general_contact], or of a "
                 "body with itself.",
          .keys = {
              {.name = "bodies",
               .type = KeyType::names,
               .required = true,
               .doc = "the two bodies (or one, for its self-contact)"},
              {.name = "kind",
               .type = KeyType::choice,
               .choices = {"frictionless", "stick", "coulomb"},
               .doc = "the pair's kind (default: [general_contact] `kind`); a pair sets kind, passes or both"},
              {.name = "friction",
               .type = KeyType::number,
               .default_value = "0",
               .min = at_least(0),
               .doc = "kind = \"coulomb\": μ"},
              {.name = "passes",
               .type = KeyType::integer,
               .min = at_least(1),
               .max = at_most(2),
               .doc = "the pair's passes (default: [general_contact] `passes`); 2 only for two deformable bodies, "
                      "frictionless"},
          }};
}

SectionSpec active_set_section() {
  return {.name = "active_set",
          .doc = "Control of the contact active set.",
          .keys = {
              {.name = "max_passes",
               .type = KeyType::integer,
               .default_value = "30",
               .min = at_least(1),
               .doc = "solves of one step before giving up on an active set that keeps changing"},
              {.name = "scheme",
               .type = KeyType::choice,
               .default_value = "persistent",
               .choices = {"paper", "persistent"},
               .doc = "`persistent`: after each step the relative velocity of the slaves in contact is set to "
                      "zero and its kinetic energy given back to the bodies' motion, so that nodes in sustained "
                      "contact do not chatter (E, L, J kept exactly; docs/theory.md); `paper`: the mid-point "
                      "velocity alone, as in the paper (and `locate_impacts` then defaults to `false`)"},
              {.name = "locate_impacts",
               .type = KeyType::boolean,
               .default_value = "true",
               .doc = "end a step early where a slave would meet its master with a gap above `gap_tolerance`, "
                      "and go on from there at the full step, so that contact takes hold at the crossing (no "
                      "hovering gap; variable steps conserve as fixed ones, docs/theory.md); meant for "
                      "`scheme = \"persistent\"`: with the paper's velocity, slaves bounce off at every "
                      "activation and each return is another split; `false`: a slave is activated holding "
                      "the gap it had at the start of the step, as in the paper; the default is `false` with "
                      "`scheme = \"paper\"`"},
              {.name = "gap_tolerance",
               .type = KeyType::number,
               .default_value = "1e-3",
               .min = above(0),
               .max = below(1),
               .doc = "largest gap a slave meeting its master anew may be activated with, as a fraction of the "
                      "longest edge of its slave facets (with `locate_impacts`)"},
              {.name = "cluster_tolerance",
               .type = KeyType::number,
               .default_value = "0.1",
               .min = above(0),
               .max = below(1),
               .doc = "the same for an impact that follows the first of its pair (with `locate_impacts`): any "
                      "slave of a pair in contact, or that had a slave activated or released within two steps "
                      "(contact that spreads, a patch whose nodes rattle); such impacts are taken together, each "
                      "held at the gap it has up to this, instead of each cutting a step; at least "
                      "`gap_tolerance`"},
              {.name = "locate_releases",
               .type = KeyType::boolean,
               .default_value = "false",
               .doc = "shorten the steps ahead of a lift-off: where the force of a slave in contact, falling at its "
                      "rate over the last two steps, would reach zero within four steps, the steps shrink towards "
                      "that time, so that it lets go with less than about 1 % of the mean force left in the step "
                      "before rather than a step's unloading late (docs/theory.md), and grow back after it; needs "
                      "`scheme = \"persistent\"`; `false`: the scenario's step throughout"},
          }};
}

}  // namespace

const std::vector<SectionSpec>& scenario_sections() {
  static const std::vector<SectionSpec> sections = {
      top_level(),        time_section(), newton_section(),   solver_section(),  loads_section(),   output_section(),     body_section(),
      material_section(), mesh_section(), rotate_section(), boundary_section(), contact_section(), active_set_section(),
      general_contact_section(), general_contact_pair_section(), load_section(),     curve_section(),
  };
  return sections;
}

const SectionSpec& scenario_section(std::string_view name) {
  for (const auto& section : scenario_sections()) {
    if (section.name == name) return section;
  }
  throw std::out_of_range("no scenario section '" + std::string(name) + "'");
}

std::string key_names(const SectionSpec& section) {
  std::string names;
  for (const auto& key : section.keys) {
    if (!names.empty()) names += ", ";
    names += key.name;
  }
  return names;
}

}  // namespace conserve::io
