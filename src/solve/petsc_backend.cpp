// PETSc KSP + PC on the assembled compressed rows (no copy: PETSc's AIJ matrix uses our
// arrays). PETSc is started on first use; its errors come back as return codes (no
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
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include "backends.hpp"

namespace vrsph {

std::string default_petsc_options(int /*dimension*/) {
  // Right-preconditioned flexible GMRES: the convergence test sees the true residual, so
  // rtol means what it says. BoomerAMG with PMIS coarsening and extended+i interpolation
  // (the usual choice for non-symmetric M-matrices) and Jacobi smoothing, which beat
  // HMIS, hybrid Gauss-Seidel, aggressive coarsening, P_max 2 and threshold 0.5 in time
  // to solution on VRSPH Example 5 in 2D (10^6) and 3D (2.3 10^5); the same settings won
  // in both dimensions. Measured table: docs/solvers.md.
  return "-ksp_type fgmres -ksp_gmres_restart 50 -pc_type hypre -pc_hypre_type boomeramg "
         "-pc_hypre_boomeramg_coarsen_type PMIS -pc_hypre_boomeramg_interp_type ext+i "
         "-pc_hypre_boomeramg_P_max 4 -pc_hypre_boomeramg_strong_threshold 0.25 "
         "-pc_hypre_boomeramg_relax_type_all Jacobi";
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

void finalise_petsc() {
  PetscBool done = PETSC_FALSE;
  if (PetscFinalized(&done) == 0 && !done) PetscFinalize();
}

void start_petsc() {
  PetscBool started = PETSC_FALSE;
  PetscInitialized(&started);
  if (started) return;
  // No signal handler (a crash stays a crash, not a PETSc message), no .petscrc files
  // (options come only from vrsph's defaults, PETSC_OPTIONS and --petsc-options).
  static char arg0[] = "vrsph", arg1[] = "-no_signal_handler", arg2[] = "-skip_petscrc", arg3[] = "-options_left",
              arg4[] = "0";
  static char* args[] = {arg0, arg1, arg2, arg3, arg4, nullptr};
  int argc = 5;
  char** argv = args;
  const PetscErrorCode code = PetscInitialize(&argc, &argv, nullptr, nullptr);
  if (code != 0)
    throw ConfigError(concat("PETSc could not start (error ", code,
                             "; MPI may be unavailable); use --solver umfpack or --solver bicgstab"));
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  std::atexit(finalise_petsc);
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

// Everything PETSc allocated for one solve, destroyed in reverse order whatever happens.
struct Session {
  PetscOptions options = nullptr;
  bool pushed = false;
  Mat A = nullptr;
  Vec b = nullptr, x = nullptr;
  KSP ksp = nullptr;
  ~Session() {
    if (ksp) KSPDestroy(&ksp);
    if (x) VecDestroy(&x);
    if (b) VecDestroy(&b);
    if (A) MatDestroy(&A);
    if (pushed) PetscOptionsPop();
    if (options) PetscOptionsDestroy(&options);
  }
};

struct MonitorContext {
  SolveReport* report;
  const SolverOptions* options;
};

PetscErrorCode monitor(KSP, PetscInt it, PetscReal rnorm, void* ctx) {
  auto* m = static_cast<MonitorContext*>(ctx);
  try {  // no C++ exception may cross PETSc's C frames: it becomes a PETSc error code
    m->report->residual_history.push_back(rnorm);
    if (m->options->monitor) m->options->monitor(static_cast<int>(it), rnorm);
  } catch (...) {
    return PETSC_ERR_USER;
  }
  return 0;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void solve_petsc(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep) {
  const std::lock_guard<std::mutex> lock(petsc_mutex);
  start_petsc();
  Session s;
  // Options: vrsph's defaults, then PETSC_OPTIONS, then the caller's (later ones win), in
  // a database of this solve's own so that one solve's options never leak into the next.
  const char* env = std::getenv("PETSC_OPTIONS");
  const std::string from_env = env ? env : "";
  call(PetscOptionsCreate(&s.options), "options");
  call(PetscOptionsInsertString(s.options, default_petsc_options(o.dimension).c_str()), "default options");
  call(PetscOptionsInsertString(s.options, from_env.c_str()), "options from PETSC_OPTIONS", Blame::Options);
  call(PetscOptionsInsertString(s.options, o.petsc_options.c_str()), "options '" + o.petsc_options + "'",
       Blame::Options);
  call(PetscOptionsPush(s.options), "options");
  s.pushed = true;

  const auto m = static_cast<PetscInt>(sys.size());
  static_assert(sizeof(PetscInt) == sizeof(Index) && sizeof(PetscScalar) == sizeof(Real),
                "PETSc's index and scalar types must match vrsph's for the no-copy matrix");
  auto& A = const_cast<CsrMatrix&>(sys.A);  // PETSc only reads the arrays (the matrix is never modified)
  // Rows divided by their diagonal: Laplacian rows (negative diagonal) and flux rows of
  // Neumann particles (positive diagonal, one power of h smaller) then look alike to the
  // AMG. Without it, mixed problems took 196 iterations at 4 10^5 unknowns and 810 at 10^6
  // instead of ~20. The index arrays are shared; only the values are copied.
  std::vector<Real> scaled;
  Eigen::VectorXd rhs;
  Real* a_values = A.valuePtr();
  const Real* b_values = sys.b.data();
  if (o.scale_rows) {
    scaled.assign(A.valuePtr(), A.valuePtr() + A.nonZeros());
    rhs = sys.b;
#pragma omp parallel for schedule(static)
    for (Index d = 0; d < m; ++d) {
      Real diagonal = 0;
      for (Index k = A.outerIndexPtr()[d]; k < A.outerIndexPtr()[d + 1]; ++k)
        if (A.innerIndexPtr()[k] == d) diagonal = A.valuePtr()[k];
      if (diagonal == 0 || !std::isfinite(diagonal)) continue;
      for (Index k = A.outerIndexPtr()[d]; k < A.outerIndexPtr()[d + 1]; ++k) scaled[static_cast<std::size_t>(k)] /= diagonal;
      rhs[d] /= diagonal;
    }
    a_values = scaled.data();
    b_values = rhs.data();
  }
  call(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, m, m, A.outerIndexPtr(), A.innerIndexPtr(), a_values, &s.A),
       "matrix");
  call(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, m, b_values, &s.b), "vector");
  call(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, m, x.data(), &s.x), "vector");
  call(KSPCreate(PETSC_COMM_SELF, &s.ksp), "KSP");
  call(KSPSetOperators(s.ksp, s.A, s.A), "KSP");
  call(KSPSetTolerances(s.ksp, o.rtol, PETSC_DEFAULT, PETSC_DEFAULT, o.max_iterations), "KSP");
  MonitorContext ctx{&rep, &o};
  call(KSPMonitorSet(s.ksp, monitor, &ctx, nullptr), "KSP");
  call(KSPSetFromOptions(s.ksp), "options", Blame::Options);

  PetscReal rtol = 0, abstol = 0, dtol = 0;
  PetscInt max_it = 0;
  call(KSPGetTolerances(s.ksp, &rtol, &abstol, &dtol, &max_it), "KSP");
  if (!(rtol > 0 && rtol < 1) || max_it < 1)
    throw ConfigError(concat("PETSc options give the relative tolerance ", rtol, " and iteration cap ", max_it,
                             ": the tolerance must be in (0, 1) and the cap at least 1"));

  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  PC pc = nullptr;
  call(KSPGetType(s.ksp, &ksp_type), "KSP");
  call(KSPGetPC(s.ksp, &pc), "PC");
  call(PCGetType(pc, &pc_type), "PC");
  rep.solver = concat("petsc ", ksp_type ? ksp_type : "?", "+", pc_type ? pc_type : "?");
  if (pc_type && std::string(pc_type) == PCHYPRE) {
    const char* hypre = nullptr;
    call(PCHYPREGetType(pc, &hypre), "PC");
    rep.solver += concat("(", hypre ? hypre : "?", ")");
  }

  const auto t0 = std::chrono::steady_clock::now();
  call(KSPSetUp(s.ksp), concat("preconditioner set-up (", rep.solver, ")"));
  rep.seconds_setup = since(t0);
  call(KSPSolve(s.ksp, s.b, s.x), concat("solve (", rep.solver, ")"));
  KSPConvergedReason reason;
  PetscInt its = 0;
  call(KSPGetConvergedReason(s.ksp, &reason), "KSP");
  call(KSPGetIterationNumber(s.ksp, &its), "KSP");
  rep.iterations = static_cast<int>(its);
  rep.reason = to_lower(KSPConvergedReasons[reason]);
  rep.success = reason > 0;
  if (!rep.success)
    rep.message = concat(rep.solver, " stopped without converging: ", rep.reason, " after ", its, " iterations");

  // Options the caller gave that no object read: a misspelt name or one that does not
  // apply to the chosen KSP/PC would otherwise be ignored in silence.
  PetscInt left = 0;
  char **names = nullptr, **values = nullptr;
  if (PetscOptionsLeftGet(s.options, &left, &names, &values) == 0) {
    // Only the caller's: PETSC_OPTIONS also feeds PETSc's start-up (-log_view, -malloc_debug...).
    const std::vector<std::string> given = option_names(o.petsc_options);
    for (PetscInt k = 0; k < left; ++k) {
      const std::string name = to_lower(names[k]);
      if (std::find(given.begin(), given.end(), name) != given.end())
        rep.warnings.push_back(concat("PETSc option -", name, " was given but not used (misspelt, or it does not apply "
                                      "to ", rep.solver, ")"));
    }
    PetscOptionsLeftRestore(s.options, &left, &names, &values);
  }
}

}  // namespace detail
}  // namespace vrsph
