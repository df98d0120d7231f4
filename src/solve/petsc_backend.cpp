// SPDX-License-Identifier: BSD-3-Clause
// PETSc KSP + PC on the assembled compressed rows (no copy: PETSc's AIJ matrix uses our
// arrays), set up once per matrix and reused for every right-hand side. PETSc is started on first use; its errors come back as return codes (no
// traceback on stderr) and become typed exceptions that keep PETSc's own text: bad
// options -> ConfigError, out of memory -> ResourceError, other failures -> NumericalError.
// A KSP that stops without converging is a failed SolveReport, like every other back-end.
#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <utility>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/core/parse.hpp>
#include "../parallel/petsc_runtime.hpp"
#include "backends.hpp"

namespace vrsph {

namespace {
// On top of the smoother below: BoomerAMG applied as two V-cycles whose up-sweeps are hybrid
// Gauss-Seidel (Gauss-Seidel within a process, Jacobi across processes). With one Jacobi-smoothed
// V-cycle the first two FGMRES iterations gained nothing (the correction's rough part raised the
// true residual tenfold: CG measured in that norm showed it) and each later one divided the
// residual by 4-5; with these, 10 iterations instead of 19 at 10^6 2D particles and 14 instead of
// 24 in 3D (3.6e5), the solve's time unchanged within this machine's spread (medians of six runs
// at 4.9e5 particles: 2.72 against 2.75 s). Measured over the problem classes: docs/solvers.md.
constexpr const char* kFewerIterationOptions =
    "-pc_hypre_boomeramg_max_iter 2 -pc_hypre_boomeramg_relax_type_up SOR/Jacobi";
constexpr const char* kRelaxAll = "-pc_hypre_boomeramg_relax_type_all";
constexpr const char* kRelaxUp = "-pc_hypre_boomeramg_relax_type_up";
}  // namespace

std::string default_petsc_options(int dimension, bool reused_setup, bool two_cycles) {
  // Right-preconditioned flexible GMRES: the convergence test sees the true residual, so
  // rtol means what it says. BoomerAMG with PMIS coarsening and extended+i interpolation
  // (the usual choice for non-symmetric M-matrices) and Jacobi smoothing, which beat
  // HMIS, hybrid Gauss-Seidel on every sweep, P_max 2 and threshold 0.5 in time to solution on
  // VRSPH Example 5 in 2D (10^6) and 3D (2.3 10^5). Measured table: docs/solvers.md. Then, with
  // two_cycles, two V-cycles per application whose up-sweeps are hybrid Gauss-Seidel
  // (kFewerIterationOptions): about half the iterations at the same time (docs/solvers.md, "Ten
  // iterations at no extra time").
  std::string o = "-ksp_type fgmres -ksp_gmres_restart 50 -pc_type hypre -pc_hypre_type boomeramg "
                  "-pc_hypre_boomeramg_coarsen_type PMIS -pc_hypre_boomeramg_interp_type ext+i "
                  "-pc_hypre_boomeramg_P_max 4 -pc_hypre_boomeramg_strong_threshold 0.25 "
                  "-pc_hypre_boomeramg_relax_type_all Jacobi";
  if (two_cycles) o.append(" ").append(kFewerIterationOptions);
  // 3D: aggressive coarsening on the first level. A 3D row couples about four times the
  // neighbours of a 2D one, and the default coarsening's operator complexity made the set-up
  // most of the solve; aggressive coarsening takes 1.5-2 times the iterations but a third of
  // the set-up: the solve 0.46-0.90 x its time over seven 3D problems at 1e5 and 3.6e5
  // unknowns (docs/solvers.md, "Aggressive coarsening in 3D"). In 2D it needed 54 iterations
  // instead of 19 and took 1.4 x the time (4.9e5 unknowns). Not where one set-up serves many
  // solves (a flow's stages reuse the hierarchy): there the iterations are the cost, and the
  // 3D Beltrami flow took 1.3-1.6 x the time a step with it.
  if (dimension == 3 && !reused_setup) o += " -pc_hypre_boomeramg_agg_nl 1";
  return o;
}

namespace detail {
namespace {

std::mutex petsc_mutex;  // PETSc is not thread-safe; one solve at a time

enum class Blame { Options, Solve };

[[noreturn]] void fail(PetscErrorCode code, const std::string& what, Blame blame) {
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  std::string msg = concat("PETSc ", what, ": ", specific && *specific ? specific : "error", " (PETSc error ", code,
                           text ? concat(": ", text) : std::string(), ")");
  if (code == PETSC_ERR_MEM) throw ResourceError(msg + "; use fewer particles or a lighter preconditioner");
  if (blame == Blame::Options) throw ConfigError(msg);
  throw NumericalError(msg);
}

void call(PetscErrorCode code, const std::string& what, Blame blame = Blame::Solve) {
  if (code != 0) fail(code, what, blame);
}

// Option names (without the dash, lower case) in a PETSc option string: words that start
// with '-' and a letter (so "-1e-3" is a value).
std::vector<std::string> option_names(const std::string& s) {
  std::vector<std::string> names;
  std::istringstream in(s);
  for (std::string w; in >> w;)
    if (w.size() > 1 && w[0] == '-' && std::isalpha(static_cast<unsigned char>(w[1]))) names.push_back(to_lower(w.substr(1)));
  return names;
}

struct MonitorContext {
  SolveReport* report = nullptr;  // the report of the solve under way
  std::function<void(int, Real)> callback;
  bool interrupted = false;       // a stop was asked for (check_interrupt): the solve ends
};

PetscErrorCode monitor(KSP, PetscInt it, PetscReal rnorm, void* ctx) {
  auto* m = static_cast<MonitorContext*>(ctx);
  try {  // no C++ exception may cross PETSc's C frames: it becomes a PETSc error code
    if (m->report) m->report->residual_history.push_back(rnorm);
    if (m->callback) m->callback(static_cast<int>(it), rnorm);
    if (interrupt_pending(0, 1)) {
      m->interrupted = true;
      return PETSC_ERR_USER;
    }
  } catch (...) {
    return PETSC_ERR_USER;
  }
  return 0;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The options database of one back-end on PETSc's stack for the duration of a call: the
// KSP reads its options at set-up and some (viewers, -ksp_converged_reason) at each solve.
class PushedOptions {
 public:
  explicit PushedOptions(PetscOptions o) { call(PetscOptionsPush(o), "options"); }
  ~PushedOptions() { PetscOptionsPop(); }
  PushedOptions(const PushedOptions&) = delete;
  PushedOptions& operator=(const PushedOptions&) = delete;
};

// One matrix set up: the KSP with its preconditioner, kept for every right-hand side.
// Everything PETSc allocated is destroyed in reverse order whatever happens.
class PetscBackend final : public Backend {
 public:
  PetscBackend(const CsrMatrix& A, const SolverOptions& o) {
    const std::lock_guard<std::mutex> lock(petsc_mutex);
    start_petsc();
    load_options(o);
    const PushedOptions pushed(options_);
    create_matrix(A, o);
    create_ksp(o);
    const auto t0 = std::chrono::steady_clock::now();
    call(KSPSetUp(ksp_), concat("preconditioner set-up (", name, ")"));
    seconds_setup = since(t0);
    warn_unused_options(o);
  }

  ~PetscBackend() override {
    const std::lock_guard<std::mutex> lock(petsc_mutex);
    if (ksp_) KSPDestroy(&ksp_);
    if (A_) MatDestroy(&A_);
    if (options_) PetscOptionsDestroy(&options_);
  }

  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep) override {
    const std::lock_guard<std::mutex> lock(petsc_mutex);
    const PushedOptions pushed(options_);
    solve_locked(b, x, rep, row_scale_);
  }

  // Another matrix of the same size (the next stage of moving particles), solved by this KSP
  // with the preconditioner set up for this one (KSPSetReusePreconditioner): no new AMG
  // hierarchy. The operator is the new matrix, rows scaled by its own diagonal.
  bool solve_other(const CsrMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep, Real rtol,
                   int max_iterations) override {
    if (distributed_ || A.rows() != m_ || A.cols() != m_) return false;
    const std::lock_guard<std::mutex> lock(petsc_mutex);
    const PushedOptions pushed(options_);
    PetscReal rtol0 = 0, abstol0 = 0, dtol0 = 0;
    PetscInt max_it0 = 0;
    call(KSPGetTolerances(ksp_, &rtol0, &abstol0, &dtol0, &max_it0), "KSP");
    std::vector<Real> values, scale;
    scaled_copy(A, 0, scale_, values, scale);
    auto& Am = const_cast<CsrMatrix&>(A);  // PETSc only reads the arrays
    struct Restore {  // this matrix and its tolerances back on every path, exceptions included
      KSP ksp;
      Mat own, other;
      PetscReal rtol, abstol, dtol;
      PetscInt max_it;
      ~Restore() {
        KSPSetOperators(ksp, own, own);
        KSPSetTolerances(ksp, rtol, abstol, dtol, max_it);
        if (other) MatDestroy(&other);
      }
    } restore{ksp_, A_, nullptr, rtol0, abstol0, dtol0, max_it0};
    call(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, m_, m_, Am.outerIndexPtr(), Am.innerIndexPtr(),
                                   scale_ ? values.data() : Am.valuePtr(), &restore.other),
         "matrix");
    const Mat other = restore.other;
    if (balance_) balance_columns(other, scale);  // in `values`, this call's copy
    call(KSPSetReusePreconditioner(ksp_, PETSC_TRUE), "KSP");
    call(KSPSetOperators(ksp_, other, A_), "KSP");
    call(KSPSetTolerances(ksp_, rtol, abstol0, dtol0, max_iterations), "KSP");
    solve_locked(b, x, rep, scale);
    return true;
  }

 private:
  void solve_locked(const Eigen::VectorXd& b, Eigen::VectorXd& x, SolveReport& rep, const std::vector<Real>& row_scale) {
    if (x.size() != m_) x = Eigen::VectorXd::Zero(m_);
    Eigen::VectorXd rhs = b;
    if (!row_scale.empty())
      for (Index d = 0; d < m_; ++d) rhs[d] *= row_scale[static_cast<std::size_t>(d)];
    Vec bv = nullptr, xv = nullptr;
    struct Vectors {  // destroyed on every path, exceptions included
      Vec* b;
      Vec* x;
      ~Vectors() {
        if (*x) VecDestroy(x);
        if (*b) VecDestroy(b);
      }
    } guard{&bv, &xv};
    if (distributed_) {
      call(VecCreateMPIWithArray(comm_, 1, m_, PETSC_DETERMINE, rhs.data(), &bv), "vector");
      call(VecCreateMPIWithArray(comm_, 1, m_, PETSC_DETERMINE, x.data(), &xv), "vector");
    } else {
      call(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, m_, rhs.data(), &bv), "vector");
      call(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, m_, x.data(), &xv), "vector");
    }
    // The caller's x as the initial guess (a time step's previous solution); zero: PETSc's default.
    call(KSPSetInitialGuessNonzero(ksp_, takes_guess_ && !x.isZero(0) ? PETSC_TRUE : PETSC_FALSE), "KSP");
    monitor_.report = &rep;
    const PetscErrorCode code = KSPSolve(ksp_, bv, xv);
    monitor_.report = nullptr;
    if (std::exchange(monitor_.interrupted, false)) check_interrupt();  // throws Interrupted
    call(code, concat("solve (", name, ")"));
    KSPConvergedReason converged;
    PetscInt its = 0;
    call(KSPGetConvergedReason(ksp_, &converged), "KSP");
    call(KSPGetIterationNumber(ksp_, &its), "KSP");
    rep.iterations = static_cast<int>(its);
    rep.reason = to_lower(KSPConvergedReasons[converged]);
    rep.success = converged > 0;
    if (distributed_) rep.residual = true_residual(bv, xv, b);
    if (!rep.success)
      rep.message = concat(name, " stopped without converging: ", rep.reason, " after ", its, " iterations");
  }

  // Options: vrsph's defaults, then PETSC_OPTIONS, then the caller's (later ones win), in
  // a database of this back-end's own so that one solver's options never leak into the next.
  void load_options(const SolverOptions& o) {
    const char* env = std::getenv("PETSC_OPTIONS");
    const std::string from_env = env ? env : "";
    call(PetscOptionsCreate(&options_), "options");
    call(PetscOptionsInsertString(options_, default_petsc_options(o.dimension, o.reused_setup, o.two_cycles && o.scale_rows).c_str()), "default options");
    call(PetscOptionsInsertString(options_, from_env.c_str()), "options from PETSC_OPTIONS", Blame::Options);
    call(PetscOptionsInsertString(options_, o.petsc_options.c_str()), "options '" + o.petsc_options + "'",
         Blame::Options);
    // PETSc applies relax_type_up after relax_type_all: a caller's smoother for all sweeps would
    // leave our default up-sweep in place. Theirs wins.
    const std::vector<std::string> given = option_names(from_env + " " + o.petsc_options);
    const auto named = [&](const char* option) { return std::find(given.begin(), given.end(), option + 1) != given.end(); };
    if (named(kRelaxAll) && !named(kRelaxUp)) call(PetscOptionsClearValue(options_, kRelaxUp), "options");
  }

  void create_matrix(const CsrMatrix& A, const SolverOptions& o) {
    m_ = static_cast<PetscInt>(A.rows());
    static_assert(sizeof(PetscInt) == sizeof(Index) && sizeof(PetscScalar) == sizeof(Real),
                  "PETSc's index and scalar types must match vrsph's for the no-copy matrix");
    // Distributed: this rank's rows, after those of the lower ranks, with global columns.
    distributed_ = o.communicator.distributed();
    comm_ = distributed_ ? MPI_Comm_f2c(o.communicator.fortran_handle()) : PETSC_COMM_SELF;
    PetscInt first_row = 0;
    if (distributed_) MPI_Exscan(&m_, &first_row, 1, MPIU_INT, MPI_SUM, comm_);
    if (distributed_ && o.communicator.rank() == 0) first_row = 0;
    auto& Am = const_cast<CsrMatrix&>(A);  // PETSc only reads the arrays (the matrix is never modified)
    scale_ = o.scale_rows;
    const Real* a_values = o.scale_rows ? scale_rows(Am, first_row) : Am.valuePtr();
    if (distributed_) {
      // MPIAIJ from the rows: PETSc splits them into the diagonal and off-diagonal blocks and
      // preallocates both from the row pattern (a copy: the local blocks are PETSc's own).
      const auto global = static_cast<PetscInt>(A.cols());
      call(MatCreateMPIAIJWithArrays(comm_, m_, m_, global, global, Am.outerIndexPtr(), Am.innerIndexPtr(), a_values, &A_),
           "matrix");
      scaled_.clear();
      scaled_.shrink_to_fit();
    } else {
      call(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, m_, m_, Am.outerIndexPtr(), Am.innerIndexPtr(),
                                     const_cast<Real*>(a_values), &A_),
           "matrix");
    }
    balance_ = o.scale_rows && o.balance_columns;
    if (balance_) balance_columns(A_, row_scale_);  // serial: in our copy of the values
  }

  // Rows divided by their diagonal: Laplacian rows (negative diagonal) and flux rows of
  // Neumann particles (positive diagonal, one power of h smaller) then look alike to the
  // AMG. Without it, mixed problems took 196 iterations at 4 10^5 unknowns and 810 at 10^6
  // instead of ~20. The index arrays are shared; only the values are copied.
  const Real* scale_rows(const CsrMatrix& Am, PetscInt first_row) {
    scaled_copy(Am, first_row, true, scaled_, row_scale_);
    return scaled_.data();
  }

  // values: A's divided row by row by the diagonal (first_row: the rank's first global row),
  // scale: those factors (1 where the diagonal is 0 or not finite); nothing when !scale_rows.
  void scaled_copy(const CsrMatrix& Am, PetscInt first_row, bool scale_rows, std::vector<Real>& values,
                   std::vector<Real>& scale) const {
    values.clear();
    scale.clear();
    if (!scale_rows) return;
    values.assign(Am.valuePtr(), Am.valuePtr() + Am.nonZeros());
    scale.assign(static_cast<std::size_t>(m_), 1.0);
#pragma omp parallel for schedule(static)
    for (Index d = 0; d < m_; ++d) {
      Real diagonal = 0;
      for (Index k = Am.outerIndexPtr()[d]; k < Am.outerIndexPtr()[d + 1]; ++k)
        if (Am.innerIndexPtr()[k] == first_row + d) diagonal = Am.valuePtr()[k];
      if (diagonal == 0 || !std::isfinite(diagonal)) continue;
      scale[static_cast<std::size_t>(d)] = 1 / diagonal;
      for (Index k = Am.outerIndexPtr()[d]; k < Am.outerIndexPtr()[d + 1]; ++k) values[static_cast<std::size_t>(k)] /= diagonal;
    }
  }

  // Rows weighted by d, an estimate of the left null vector of the row-scaled matrix S
  // (diagonal 1): two Jacobi sweeps on S^T d = 0 from d = 1, d_j = -sum_(i != j) d_i S_ij,
  // normalised to mean 1 and kept in [0.1, 10]. A particle Laplacian's rows sum to zero (it
  // is exact on constants) but its columns do not: each row has its own volumes, and
  // VRSPH's rows pick ~10 of ~28 neighbours. BoomerAMG restricts with R = P^T, which for
  // such a matrix misses the left near-null vector; weighted by d, the columns sum to
  // about zero as well. Example 5, perturbed, VRSPH (2D, 10^6 unknowns): 24 -> 19
  // FGMRES iterations, the solve (set-up included) 11-13 % shorter (docs/solvers.md). Scales: each
  // row's factor multiplied by its d; the convergence test then sees D (b - A x) with
  // this D, and the true residual is measured as before.
  void balance_columns(Mat S, std::vector<Real>& scale) {
    Vec diag = nullptr, d = nullptr, t = nullptr;
    struct Vectors {
      Vec *a, *b, *c;
      ~Vectors() {
        for (Vec* v : {a, b, c})
          if (*v) VecDestroy(v);
      }
    } guard{&diag, &d, &t};
    call(MatCreateVecs(S, &d, &t), "balance");
    call(VecDuplicate(d, &diag), "balance");
    call(MatGetDiagonal(S, diag), "balance");
    call(VecSet(d, 1.0), "balance");
    PetscInt n_global = 0;
    call(VecGetSize(d, &n_global), "balance");
    for (int sweep = 0; sweep < 2; ++sweep) {
      call(MatMultTranspose(S, d, t), "balance");
      PetscScalar* dv = nullptr;
      const PetscScalar *tv = nullptr, *gv = nullptr;
      call(VecGetArray(d, &dv), "balance");
      call(VecGetArrayRead(t, &tv), "balance");
      call(VecGetArrayRead(diag, &gv), "balance");
      for (PetscInt j = 0; j < m_; ++j) {
        const Real g = gv[j];
        const Real next = g != 0 && std::isfinite(g) ? -(tv[j] - g * dv[j]) / g : 1.0;
        dv[j] = std::isfinite(next) && next > 0 ? next : 0.0;  // clamped below
      }
      VecRestoreArrayRead(diag, &gv);
      VecRestoreArrayRead(t, &tv);
      VecRestoreArray(d, &dv);
      PetscScalar sum = 0;
      call(VecSum(d, &sum), "balance");
      const Real mean = n_global > 0 ? sum / static_cast<Real>(n_global) : 1.0;
      call(VecGetArray(d, &dv), "balance");
      for (PetscInt j = 0; j < m_; ++j) dv[j] = mean > 0 ? std::clamp(dv[j] / mean, 0.1, 10.0) : 1.0;
      VecRestoreArray(d, &dv);
    }
    call(MatDiagonalScale(S, d, nullptr), "balance");
    const PetscScalar* dv = nullptr;
    call(VecGetArrayRead(d, &dv), "balance");
    for (PetscInt j = 0; j < m_; ++j) scale[static_cast<std::size_t>(j)] *= dv[j];
    VecRestoreArrayRead(d, &dv);
  }

  // The KSP with the options applied; its tolerances checked and its name ("petsc gmres+hypre(boomeramg)").
  void create_ksp(const SolverOptions& o) {
    call(KSPCreate(comm_, &ksp_), "KSP");
    call(KSPSetOperators(ksp_, A_, A_), "KSP");
    call(KSPSetTolerances(ksp_, o.rtol, PETSC_DEFAULT, PETSC_DEFAULT, o.max_iterations), "KSP");
    monitor_.callback = o.monitor;
    call(KSPMonitorSet(ksp_, monitor, &monitor_, nullptr), "KSP");
    call(KSPSetFromOptions(ksp_), "options", Blame::Options);

    PetscReal rtol = 0, abstol = 0, dtol = 0;
    PetscInt max_it = 0;
    call(KSPGetTolerances(ksp_, &rtol, &abstol, &dtol, &max_it), "KSP");
    if (!(rtol > 0 && rtol < 1) || max_it < 1)
      throw ConfigError(concat("PETSc options give the relative tolerance ", rtol, " and iteration cap ", max_it,
                               ": the tolerance must be in (0, 1) and the cap at least 1"));

    KSPType ksp_type = nullptr;
    PCType pc_type = nullptr;
    PC pc = nullptr;
    call(KSPGetType(ksp_, &ksp_type), "KSP");
    call(KSPGetPC(ksp_, &pc), "PC");
    call(PCGetType(pc, &pc_type), "PC");
    name = concat("petsc ", ksp_type ? ksp_type : "?", "+", pc_type ? pc_type : "?");
    takes_guess_ = !(ksp_type && std::string(ksp_type) == KSPPREONLY);  // preonly refuses an initial guess
    if (pc_type && std::string(pc_type) == PCHYPRE) {
      const char* hypre = nullptr;
      call(PCHYPREGetType(pc, &hypre), "PC");
      name += concat("(", hypre ? hypre : "?", ")");
    }
  }

  // Options the caller gave that no object read: a misspelt name or one that does not
  // apply to the chosen KSP/PC would otherwise be ignored in silence.
  void warn_unused_options(const SolverOptions& o) {
    PetscInt left = 0;
    char **names = nullptr, **values = nullptr;
    if (PetscOptionsLeftGet(options_, &left, &names, &values) != 0) return;
    // Only the caller's: PETSC_OPTIONS also feeds PETSc's start-up (-log_view, -malloc_debug...).
    const std::vector<std::string> given = option_names(o.petsc_options);
    for (PetscInt k = 0; k < left; ++k) {
      const std::string option = to_lower(names[k]);
      if (std::find(given.begin(), given.end(), option) != given.end())
        warnings.push_back(concat("PETSc option -", option, " was given but not used (misspelt, or it does not "
                                  "apply to ", name, ")"));
    }
    PetscOptionsLeftRestore(options_, &left, &names, &values);
  }

  // ||b - A x|| / ||b|| of the unscaled system over every rank: the scaled residual
  // D^-1 (b - A x) from PETSc, times the row scales D.
  Real true_residual(Vec bv, Vec xv, const Eigen::VectorXd& b) {
    Vec r = nullptr;
    call(VecDuplicate(bv, &r), "vector");
    call(MatMult(A_, xv, r), "residual");
    call(VecAYPX(r, -1.0, bv), "residual");
    const PetscScalar* rv = nullptr;
    call(VecGetArrayRead(r, &rv), "residual");
    double sums[2] = {0, 0};
    for (PetscInt d = 0; d < m_; ++d) {
      const Real rd = row_scale_.empty() ? rv[d] : rv[d] / row_scale_[static_cast<std::size_t>(d)];
      sums[0] += rd * rd;
      sums[1] += b[d] * b[d];
    }
    VecRestoreArrayRead(r, &rv);
    VecDestroy(&r);
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_);
    return std::sqrt(sums[0]) / (sums[1] > 0 ? std::sqrt(sums[1]) : 1.0);
  }

  bool distributed_ = false;
  MPI_Comm comm_ = MPI_COMM_NULL;
  PetscInt m_ = 0;
  bool takes_guess_ = true;
  PetscOptions options_ = nullptr;
  Mat A_ = nullptr;
  KSP ksp_ = nullptr;
  std::vector<Real> scaled_, row_scale_;
  bool scale_ = true;  // rows divided by their diagonal (SolverOptions::scale_rows)
  bool balance_ = true;  // and weighted by the left null vector's estimate (SolverOptions::balance_columns)
  MonitorContext monitor_;
};

}  // namespace

std::unique_ptr<Backend> prepare_petsc(const CsrMatrix& A, const SolverOptions& o) {
  return std::make_unique<PetscBackend>(A, o);
}

}  // namespace detail
}  // namespace vrsph
