#include "solver/krylov_solver.hpp"

#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "core/bytes.hpp"
#include "core/error.hpp"
#include "solver/direct_solver.hpp"
#include "solver/mumps_solver.hpp"
#include "solver/petsc_session.hpp"
#include "solver/petsc_system.hpp"
#include "solver/ranks.hpp"

namespace conserve::solver {

using petsc::check;

namespace {

/// GMRES's restart length (`-ksp_gmres_restart` may change it).
constexpr PetscInt kRestart = 60;

/// The most matrices sent to the LU in a row after GMRES stagnated; a
/// run that has become easy for GMRES again (bodies that stopped
/// spinning) comes back to it within that many tangents.
constexpr int kLongestLuRun = 32;

/// PETSc's default test, and an early end for a solve that cannot reach
/// its tolerance within the iteration limit: at the end of each restart
/// cycle the residual's reduction over that cycle, taken as the rate of
/// the cycles to come, predicts the iterations still needed; if that
/// passes the limit the solve ends now (KSP_DIVERGED_ITS), as it would
/// have at the limit, and the matrix goes to the LU (KrylovSolver::solve)
/// without the cycles that would not have reached it. A restarted GMRES
/// whose cycle barely lowers the residual stagnates (quasi-rigid bodies,
/// docs/notes/validation-history.md).
struct StagnationTest {
  PetscInt restart = kRestart;  ///< the KSP's restart length
  void* defaults = nullptr;     ///< KSPConvergedDefault's context
  PetscReal initial = 0.0;      ///< |r| at iteration 0
  PetscReal cycle_start = 0.0;  ///< |r| at the start of the current cycle
  PetscInt cycle_first = 0;     ///< the iteration it started at

  static PetscErrorCode test(KSP ksp, PetscInt n, PetscReal rnorm, KSPConvergedReason* reason, void* context) {
    auto* self = static_cast<StagnationTest*>(context);
    PetscErrorCode error = KSPConvergedDefault(ksp, n, rnorm, reason, self->defaults);
    if (error != 0 || *reason != KSP_CONVERGED_ITERATING) return error;
    if (n == 0) {
      self->initial = self->cycle_start = rnorm;
      self->cycle_first = 0;
      return 0;
    }
    // GMRES tests a restart's iteration twice (the cycle's estimate, then
    // the new cycle's true residual): the cycle is judged once.
    if (n < self->cycle_first + self->restart) return 0;
    PetscReal rtol = 0.0, atol = 0.0, dtol = 0.0;
    PetscInt limit = 0;
    error = KSPGetTolerances(ksp, &rtol, &atol, &dtol, &limit);
    if (error != 0) return error;
    const double rate = rnorm / self->cycle_start;  // per cycle
    const double target = std::max(rtol * self->initial, atol);
    self->cycle_start = rnorm;
    self->cycle_first = n;
    if (!(rnorm > target)) return 0;
    const double cycles = rate < 1.0 ? std::log(target / rnorm) / std::log(rate) : 1e300;
    if (static_cast<double>(n) + cycles * static_cast<double>(self->restart) > static_cast<double>(limit))
      *reason = KSP_DIVERGED_ITS;
    return 0;
  }

  StagnationTest() = default;
  StagnationTest(const StagnationTest&) = delete;
  StagnationTest& operator=(const StagnationTest&) = delete;
  ~StagnationTest() {
    if (defaults) KSPConvergedDefaultDestroy(defaults);
  }

  static PetscErrorCode destroy(void* context) {
    delete static_cast<StagnationTest*>(context);
    return 0;
  }
};

}  // namespace

struct KrylovSolver::Petsc {
  Preconditioner kind;
  LinearSolverSettings settings;
  /// On several ranks the system is distributed (rows by rank, block
  /// Jacobi with ILU(0) in each rank's block instead of ILU(0)); on one,
  /// the sequential matrix below.
  bool distributed = ranks::size() > 1;
  petsc::DistributedSystem system;
  ::Mat A = nullptr;
  KSP ksp = nullptr;
  ::Vec b = nullptr, x = nullptr;
  bool operators_set = false;
  std::vector<int> outer, inner;                     ///< the CSC pattern the matrix was made for
  std::vector<PetscInt> row_start, column;           ///< the PETSc matrix's (block) CSR pattern
  std::vector<int> to;                               ///< CSC position → position in the PETSc values
  int block_size = 1;                                ///< D for BAIJ, 1 for AIJ
  Eigen::MatrixXd X;                                 ///< reference coordinates (GAMG's rigid-body modes)
  std::vector<int> rank_nodes;           ///< on several ranks, the ranks' nodes (set_layout)
  const SparseMatrix* last = nullptr;    ///< the matrix of set_operator (valid until the next)
  std::unique_ptr<LinearSolver> direct;  ///< the fallback (UMFPACK, MUMPS on several ranks), made on first use
  bool direct_ready = false;             ///< the fallback holds the present matrix

  // The LU first (KrylovSolver::set_operator).
  bool gmres_matrix = false;  ///< the present matrix was set up for GMRES (then direct_ready
                              ///< tells that one of its solves stagnated and went to the LU)
  int lu_first_left = 0;      ///< matrices still to send to the LU without a GMRES attempt
  int lu_run = 1;             ///< how many the next stagnation sends

  /// Called before each new matrix: after a matrix whose GMRES stagnated,
  /// the next lu_run matrices go to the LU, and lu_run doubles for the
  /// next time (up to kLongestLuRun); a GMRES matrix that did not
  /// stagnate sets it back to one.
  void plan_lu_first() {
    if (!gmres_matrix) return;
    if (direct_ready) {
      lu_first_left = lu_run;
      lu_run = std::min(2 * lu_run, kLongestLuRun);
    } else {
      lu_run = 1;
    }
  }

  void factorize_lu(Timings* timings) {
    if (!direct) {
      if (distributed) {
        // Each rank holds its part of the system: the LU is distributed too.
        auto mumps = std::make_unique<MumpsSolver>();
        mumps->set_coordinates(X);
        mumps->set_layout(rank_nodes);
        direct = std::move(mumps);
      } else {
        direct = std::make_unique<DirectSolver>();
      }
      direct->set_timings(timings);
    }
    direct->set_operator(*last);
    direct_ready = true;
  }

  ~Petsc() { destroy(); }

  void destroy() {
    if (ksp) KSPDestroy(&ksp);
    if (distributed) return;  // the system owns them
    if (A) MatDestroy(&A);
    if (b) VecDestroy(&b);
    if (x) VecDestroy(&x);
  }

  std::uint64_t ksps = 0;  ///< KSPs made so far (generation())

  void make_ksp() {
    ++ksps;
    if (ksp) KSPDestroy(&ksp);
    check(KSPCreate(distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF, &ksp), "KSPCreate");
    check(KSPSetType(ksp, KSPGMRES), "KSPSetType");
    check(KSPGMRESSetRestart(ksp, kRestart), "KSPGMRESSetRestart");
    // Right preconditioning: the tolerance applies to |b − A x| itself.
    check(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");
    PC pc = nullptr;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (kind == Preconditioner::gamg) {
      check(PCSetType(pc, PCGAMG), "PCSetType(gamg)");
      check(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE), "PCGAMGSetReuseInterpolation");
    } else if (distributed) {
      check(PCSetType(pc, PCBJACOBI), "PCSetType(bjacobi)");
      by_default("-sub_pc_type", "ilu");
      by_default("-sub_pc_factor_shift_type", "nonzero");
    } else {
      check(PCSetType(pc, PCILU), "PCSetType(ilu)");
      check(PCFactorSetLevels(pc, 0), "PCFactorSetLevels");
      check(PCFactorSetShiftType(pc, MAT_SHIFT_NONZERO), "PCFactorSetShiftType");
    }
    check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
    PetscBool gmres = PETSC_FALSE;  // the options may have chosen another method
    check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp), KSPGMRES, &gmres), "PetscObjectTypeCompare");
    if (gmres) {
      auto stagnation = std::make_unique<StagnationTest>();
      check(KSPGMRESGetRestart(ksp, &stagnation->restart), "KSPGMRESGetRestart");
      check(KSPConvergedDefaultCreate(&stagnation->defaults), "KSPConvergedDefaultCreate");
      check(KSPSetConvergenceTest(ksp, &StagnationTest::test, stagnation.get(), &StagnationTest::destroy),
            "KSPSetConvergenceTest");
      stagnation.release();  // the KSP owns it now
    }
    operators_set = false;
  }

  /// A saddle-point system [[K, B], [C, 0]]: the model's `bodies`
  /// unknowns first, then the contact multipliers. Preconditioned by
  /// PETSc's field split with the full Schur factorisation: ILU(0) on K,
  /// and on S ≈ −C diag(K)⁻¹ B (assembled, "selfp") ILU(0).
  void split_fields(PetscInt bodies) {
    const PetscInt n = static_cast<PetscInt>(outer.size()) - 1;
    PC pc = nullptr;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    check(PCSetType(pc, PCFIELDSPLIT), "PCSetType(fieldsplit)");
    IS first = nullptr, second = nullptr;
    // Each rank names its own rows of either field.
    const PetscInt begin = distributed ? system.first_row() : 0, end = distributed ? system.end_row() : n;
    const PetscInt middle = std::clamp(bodies, begin, end);
    const MPI_Comm comm = distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
    check(ISCreateStride(comm, middle - begin, begin, 1, &first), "ISCreateStride");
    check(ISCreateStride(comm, end - middle, middle, 1, &second), "ISCreateStride");
    check(PCFieldSplitSetIS(pc, "u", first), "PCFieldSplitSetIS");
    check(PCFieldSplitSetIS(pc, "lambda", second), "PCFieldSplitSetIS");
    ISDestroy(&first);
    ISDestroy(&second);
    check(PCFieldSplitSetType(pc, PC_COMPOSITE_SCHUR), "PCFieldSplitSetType");
    check(PCFieldSplitSetSchurFactType(pc, PC_FIELDSPLIT_SCHUR_FACT_FULL), "PCFieldSplitSetSchurFactType");
    check(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_SELFP, nullptr), "PCFieldSplitSetSchurPre");
    // The program's choices for the two blocks, unless [solver]
    // petsc_options (or the command line's PETSc options) set them.
    for (const char* field : {"u", "lambda"}) {
      const std::string prefix = std::string("-fieldsplit_") + field + "_";
      by_default(prefix + "ksp_type", "preonly");
      by_default(prefix + "pc_type", distributed ? "bjacobi" : "ilu");
      by_default(prefix + (distributed ? "sub_pc_factor_shift_type" : "pc_factor_shift_type"), "nonzero");
    }
    check(PCSetFromOptions(pc), "PCSetFromOptions");
    split = true;
  }
  bool split = false;  ///< a saddle-point system has been split (name())

  /// Sets a PETSc option unless [solver] petsc_options (or the command
  /// line's PETSc options) set it.
  static void by_default(const std::string& name, const char* value) {
    PetscBool set = PETSC_FALSE;
    check(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set), "PetscOptionsHasName");
    if (!set) check(PetscOptionsSetValue(nullptr, name.c_str(), value), "PetscOptionsSetValue");
  }

  [[nodiscard]] bool same_pattern(const SparseMatrix& M) const {
    if (distributed) return system.same_pattern(M);
    return static_cast<Eigen::Index>(outer.size()) == M.outerSize() + 1 &&
           static_cast<Eigen::Index>(inner.size()) == M.nonZeros() &&
           std::equal(outer.begin(), outer.end(), M.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), M.innerIndexPtr());
  }

  /// A new PETSc matrix for the pattern of M (compressed columns → rows):
  /// point-block (BAIJ, the nodes' D × D blocks) for ILU, whose block
  /// ILU(0) and products then index blocks rather than entries; scalar
  /// (AIJ, with the block size noted) for GAMG, which needs AIJ.
  void new_matrix(const SparseMatrix& M) {
    const int n = static_cast<int>(M.rows());
    outer.assign(M.outerIndexPtr(), M.outerIndexPtr() + M.outerSize() + 1);
    // On several ranks the system keeps the pattern (and compares it).
    if (distributed)
      inner.clear();
    else
      inner.assign(M.innerIndexPtr(), M.innerIndexPtr() + M.nonZeros());
    const int dim = static_cast<int>(X.rows());
    // Node blocks only for a system of the model's own unknowns: one with
    // extra unknowns (contact multipliers) has rows that are no node's.
    const bool nodal = dim > 0 && n == static_cast<int>(X.size());
    const bool blocked = kind == Preconditioner::ilu && dim > 1 && nodal;
    if (distributed) {
      system.make(M, std::max(dim, 1), blocked, rank_nodes);
      A = system.matrix(), b = system.rhs(), x = system.solution();
      block_size = blocked ? dim : 1;
      if (kind == Preconditioner::gamg && dim > 0 && X.size() == n) set_rigid_body_modes(dim);
      operators_set = false;
      return;
    }
    if (A) MatDestroy(&A);
    check(MatCreate(PETSC_COMM_SELF, &A), "MatCreate");
    check(MatSetSizes(A, n, n, n, n), "MatSetSizes");
    if (blocked) {
      new_block_pattern(dim, n / dim);
      check(MatSetType(A, MATSEQBAIJ), "MatSetType");
      // No values: zeros (copy_values() sets them).
      check(MatSeqBAIJSetPreallocationCSR(A, dim, row_start.data(), column.data(), nullptr),
            "MatSeqBAIJSetPreallocationCSR");
    } else {
      new_scalar_pattern(n);
      check(MatSetType(A, MATSEQAIJ), "MatSetType");
      if (nodal) check(MatSetBlockSize(A, dim), "MatSetBlockSize");
      check(MatSeqAIJSetPreallocationCSR(A, row_start.data(), column.data(), nullptr), "MatSeqAIJSetPreallocationCSR");
    }
    block_size = blocked ? dim : 1;
    if (kind == Preconditioner::gamg && dim > 0 && X.size() == n) set_rigid_body_modes(dim);
    if (!b) {
      check(MatCreateVecs(A, &x, &b), "MatCreateVecs");
    } else {
      PetscInt size = 0;
      check(VecGetSize(b, &size), "VecGetSize");
      if (size != n) {
        VecDestroy(&b);
        VecDestroy(&x);
        check(MatCreateVecs(A, &x, &b), "MatCreateVecs");
      }
    }
    operators_set = false;
  }

  /// CSR of the entries; to[k] is where CSC entry k goes in the values.
  void new_scalar_pattern(int n) {
    row_start.assign(n + 1, 0);
    for (const int i : inner) ++row_start[i + 1];
    for (int i = 0; i < n; ++i) row_start[i + 1] += row_start[i];
    column.resize(inner.size());
    to.resize(inner.size());
    std::vector<PetscInt> next(row_start.begin(), row_start.end() - 1);
    for (int j = 0; j < n; ++j)  // columns in order: each row's columns come out sorted
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        const PetscInt p = next[inner[k]]++;
        column[p] = j;
        to[k] = p;
      }
  }

  /// CSR of the d × d blocks holding an entry (a block's missing entries
  /// are stored zeros); to[k] is where CSC entry k goes: SeqBAIJ keeps each
  /// block column-major, after the blocks before it. Two passes over the
  /// block columns in ascending order, as new_scalar_pattern: the first
  /// counts each block row's blocks, the second hands out their slots in
  /// the order their columns come, so each row's columns come out sorted
  /// and every entry finds its block without a search.
  void new_block_pattern(int d, int nodes) {
    std::vector<PetscInt> seen(nodes, -1);  // the last block column that met each block row
    row_start.assign(nodes + 1, 0);
    for (int J = 0; J < nodes; ++J)
      for (int k = outer[J * d]; k < outer[(J + 1) * d]; ++k)
        if (const int I = inner[k] / d; seen[I] != J) seen[I] = J, ++row_start[I + 1];
    for (int I = 0; I < nodes; ++I) row_start[I + 1] += row_start[I];
    column.resize(row_start[nodes]);
    to.resize(inner.size());
    std::vector<PetscInt> next(row_start.begin(), row_start.end() - 1);
    std::vector<PetscInt> slot(nodes, -1);  // block column J's block in each row it meets
    std::fill(seen.begin(), seen.end(), -1);
    for (int J = 0; J < nodes; ++J)
      for (int j = J * d; j < (J + 1) * d; ++j)
        for (int k = outer[j]; k < outer[j + 1]; ++k) {
          const int I = inner[k] / d;
          if (seen[I] != J) {
            seen[I] = J;
            slot[I] = next[I]++;
            column[slot[I]] = J;
          }
          to[k] = static_cast<int>(slot[I] * d * d + (j % d) * d + inner[k] % d);
        }
  }

  void set_rigid_body_modes(int dim) {
    ::Vec coordinates = nullptr;
    const PetscInt begin = distributed ? system.first_row() : 0;
    const PetscInt end = distributed ? system.end_row() : static_cast<PetscInt>(X.size());
    if (distributed)
      check(VecCreateMPI(PETSC_COMM_WORLD, end - begin, static_cast<PetscInt>(X.size()), &coordinates), "VecCreateMPI");
    else
      check(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(X.size()), &coordinates), "VecCreateSeq");
    check(VecSetBlockSize(coordinates, dim), "VecSetBlockSize");
    PetscScalar* c = nullptr;
    check(VecGetArrayWrite(coordinates, &c), "VecGetArrayWrite");
    // column-major D × nodes: node-major dofs
    if (distributed)
      system.local_entries(X.data(), c);
    else
      std::copy(X.data() + begin, X.data() + end, c);
    check(VecRestoreArrayWrite(coordinates, &c), "VecRestoreArrayWrite");
    MatNullSpace modes = nullptr;
    check(MatNullSpaceCreateRigidBody(coordinates, &modes), "MatNullSpaceCreateRigidBody");
    check(MatSetNearNullSpace(A, modes), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&modes);
    VecDestroy(&coordinates);
  }

  void copy_values(const SparseMatrix& M) {
    if (distributed) {
      system.copy_values(M);
      return;
    }
    PetscScalar* v = nullptr;
    if (block_size > 1)
      check(MatSeqBAIJGetArray(A, &v), "MatSeqBAIJGetArray");
    else
      check(MatSeqAIJGetArrayWrite(A, &v), "MatSeqAIJGetArrayWrite");
    const double* values = M.valuePtr();
    const auto size = static_cast<std::ptrdiff_t>(to.size());
    for (std::ptrdiff_t k = 0; k < size; ++k) v[to[k]] = values[k];
    if (block_size > 1) {
      check(MatSeqBAIJRestoreArray(A, &v), "MatSeqBAIJRestoreArray");
      // Assembly moves the matrix's state on, so the preconditioner
      // rebuilds (the pattern is unchanged: no work beyond a pass over rows).
      check(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    } else {
      check(MatSeqAIJRestoreArrayWrite(A, &v), "MatSeqAIJRestoreArrayWrite");
    }
  }
};

KrylovSolver::KrylovSolver(Preconditioner preconditioner, const LinearSolverSettings& settings)
    : petsc_(std::make_unique<Petsc>()) {
  petsc::ensure_initialized();
  if (preconditioner == Preconditioner::automatic)
    throw Error("KrylovSolver: the automatic preconditioner must be resolved by make_linear_solver");
  petsc_->kind = preconditioner;
  petsc_->settings = settings;
  if (!settings.petsc_options.empty())
    check(PetscOptionsInsertString(nullptr, settings.petsc_options.c_str()), "[solver] petsc_options");
  petsc_->make_ksp();
}

KrylovSolver::~KrylovSolver() = default;

std::string KrylovSolver::name() const {
  const std::string base = petsc_->kind == Preconditioner::gamg ? "GMRES + GAMG"
                           : petsc_->distributed                ? "GMRES + block Jacobi ILU(0)"
                                                                : "GMRES + ILU(0)";
  std::string name = petsc_->split ? base + ", Schur field split with multipliers" : base;
  if (petsc_->distributed) name += fmt::format(" ({} ranks)", ranks::size());
  return name;
}

std::vector<std::int64_t> KrylovSolver::row_ranges() const {
  return petsc_->distributed ? petsc_->system.row_ranges() : std::vector<std::int64_t>();
}

void KrylovSolver::set_coordinates(const Eigen::MatrixXd& X) { petsc_->X = X; }

void KrylovSolver::set_layout(const std::vector<int>& rank_nodes) { petsc_->rank_nodes = rank_nodes; }

void KrylovSolver::reset() {
  Petsc& p = *petsc_;
  p.make_ksp();  // a new KSP keeps no interpolation
  // A saddle-point matrix kept for its pattern keeps its field split.
  const auto rows = static_cast<Eigen::Index>(p.outer.size()) - 1;
  if (p.A && rows > p.X.size() && p.X.size() > 0) p.split_fields(static_cast<PetscInt>(p.X.size()));
  p.gmres_matrix = false;
  p.lu_first_left = 0;
  p.lu_run = 1;
}

void KrylovSolver::set_operator(const SparseMatrix& M) {
  Petsc& p = *petsc_;
  p.plan_lu_first();
  p.last = &M;
  p.direct_ready = false;
  // Newton's tangents follow one another closely: after one whose GMRES
  // stagnated, the next ones are likely to stagnate too, and each attempt
  // would cost a preconditioner and a restart cycle before the LU it ends
  // in. Those go to the LU first (timed and counted as its set-ups).
  p.gmres_matrix = p.lu_first_left == 0;
  if (!p.gmres_matrix) {
    --p.lu_first_left;
    count(&Timings::lu_first);
    p.factorize_lu(timings_);
    return;
  }
  ScopedTimer timer(clock(&Timings::linear_setup));
  count(&Timings::linear_setups);
  bool fresh = !p.A || !p.same_pattern(M);
  if (p.distributed) fresh = ranks::max(fresh ? 1 : 0) != 0;  // a new pattern on any rank is new on all
  if (fresh) {
    // A new pattern needs a new ordering and symbolic factorization (or a
    // new GAMG hierarchy): the PC keeps them while the matrix is the same.
    p.make_ksp();
    p.new_matrix(M);
    if (M.rows() > p.X.size() && p.X.size() > 0) p.split_fields(static_cast<PetscInt>(p.X.size()));
  }
  p.copy_values(M);
  if (!p.operators_set) {
    check(KSPSetOperators(p.ksp, p.A, p.A), "KSPSetOperators");
    p.operators_set = true;
  }
  check(KSPSetUp(p.ksp), "the preconditioner set-up");  // builds the preconditioner now, timed here
}

bool KrylovSolver::cheap_setup() const { return petsc_->gmres_matrix && petsc_->lu_first_left == 0; }

std::uint64_t KrylovSolver::generation() const { return petsc_->kind == Preconditioner::gamg ? petsc_->ksps : 0; }

std::string KrylovSolver::save_state() const {
  const Petsc& p = *petsc_;
  ByteWriter w;
  w.value(static_cast<std::uint8_t>(p.gmres_matrix));
  w.value(static_cast<std::uint8_t>(p.direct_ready));
  w.value(static_cast<std::int32_t>(p.lu_first_left));
  w.value(static_cast<std::int32_t>(p.lu_run));
  return w.bytes();
}

void KrylovSolver::load_state(const std::string& bytes) {
  Petsc& p = *petsc_;
  ByteReader r(bytes, "the linear solver's state");
  p.gmres_matrix = r.value<std::uint8_t>() != 0;
  const bool direct = r.value<std::uint8_t>() != 0;
  p.lu_first_left = r.value<std::int32_t>();
  p.lu_run = r.value<std::int32_t>();
  if (!r.at_end() || p.lu_first_left < 0 || p.lu_run < 1 || p.lu_run > kLongestLuRun)
    r.fail("the linear solver's state is malformed");
  p.direct_ready = false;
  if (direct && p.last) p.factorize_lu(timings_);
}

LinearSolve KrylovSolver::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& out, double rtol) {
  Petsc& p = *petsc_;
  if (!p.A) throw Error("KrylovSolver::solve before set_operator");
  if (p.direct_ready) return fallback(rhs, out);
  PetscInt iterations = 0;
  PetscReal residual = 0.0;
  KSPConvergedReason reason;
  // GMRES cannot go below round-off; a relative tolerance above 1 would
  // accept x = 0.
  const double tolerance = std::clamp(rtol, 1e-14, 0.5);
  {
    ScopedTimer timer(clock(&Timings::linear_solve));
    if (p.distributed) {
      p.system.set_rhs(rhs);
    } else {
      PetscScalar* v = nullptr;
      check(VecGetArrayWrite(p.b, &v), "VecGetArrayWrite");
      std::copy(rhs.data(), rhs.data() + rhs.size(), v);
      check(VecRestoreArrayWrite(p.b, &v), "VecRestoreArrayWrite");
    }
    check(KSPSetTolerances(p.ksp, tolerance, 0.0, 1e30, p.settings.max_iterations), "KSPSetTolerances");
    check(KSPSolve(p.ksp, p.b, p.x), "the GMRES solve");
    check(KSPGetIterationNumber(p.ksp, &iterations), "KSPGetIterationNumber");
    check(KSPGetResidualNorm(p.ksp, &residual), "KSPGetResidualNorm");
    check(KSPGetConvergedReason(p.ksp, &reason), "KSPGetConvergedReason");
    if (timings_) ++timings_->linear_solves, timings_->linear_iterations += iterations;
    // NaN, or a failed preconditioner, leaves nothing usable.
    if (reason == KSP_DIVERGED_NANORINF || reason == KSP_DIVERGED_PC_FAILED || reason == KSP_DIVERGED_NULL ||
        reason == KSP_DIVERGED_INDEFINITE_MAT)
      throw SolverError(fmt::format("GMRES failed after {} iterations: {}", iterations, KSPConvergedReasons[reason]));
  }
  // Running out of iterations or a breakdown near the tolerance (asked for
  // below the round-off of the right-hand side) leaves a usable iterate,
  // which Newton judges by the nonlinear residual. GMRES that stagnates
  // far from it (an ill-conditioned matrix its preconditioner cannot tame,
  // e.g. quasi-rigid bodies in contact) hands this matrix to the LU:
  // robustness first, counted as a fallback.
  if (reason < 0 && residual > 2.0 * tolerance * rhs.norm() && residual > 1e-6 * rhs.norm()) {
    if (timings_) ++timings_->linear_fallbacks;
    return fallback(rhs, out);
  }
  if (p.distributed) {
    p.system.gather_solution(out);
  } else {
    const PetscScalar* r = nullptr;
    out.resize(rhs.size());
    check(VecGetArrayRead(p.x, &r), "VecGetArrayRead");
    std::copy(r, r + rhs.size(), out.data());
    check(VecRestoreArrayRead(p.x, &r), "VecRestoreArrayRead");
  }
  if (!out.allFinite()) throw SolverError("GMRES gave a non-finite increment");
  return {static_cast<int>(iterations), static_cast<double>(residual)};
}

LinearSolve KrylovSolver::fallback(const Eigen::VectorXd& rhs, Eigen::VectorXd& out) {
  Petsc& p = *petsc_;
  if (!p.direct_ready) p.factorize_lu(timings_);
  return p.direct->solve(rhs, out, 0.0);  // on several ranks MUMPS gives every rank the same x
}

}  // namespace conserve::solver
