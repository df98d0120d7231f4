// SPDX-License-Identifier: BSD-3-Clause
// The PETSc back-end: same solution as a direct solver, the report (what ran, why it
// stopped, history), option precedence and isolation, failures as statuses or typed
// errors with PETSc's own text; and the compressed rows it borrows from the assembly.
#include <cstdlib>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/solve/solver.hpp>
#ifdef _OPENMP
#include <omp.h>
#endif
#include "test_util.hpp"

using namespace vrsph;

namespace {
// Δu = f on a perturbed cloud with VRSPH (a non-symmetric M-matrix), u = sin(3x) e^y.
struct System {
  PointCloud cloud;
  Stencil L;
  LinearSystem sys;
  explicit System(int n, const char* method = "vrsph", int dim = 2) {
    cloud = vertex_lattice(Domain::unit_box(dim), n);
    PerturbOptions po;
    po.seed = 7;
    perturb(cloud, po);
    SearchParams sp;
    sp.radius = 3 * cloud.spacing;
    const NeighbourList nl = find_neighbours(cloud, sp);
    std::vector<char> unknown;
    for (auto t : cloud.tags) unknown.push_back(t == Tag::Interior);
    L = builtin_methods().create(method)->build({cloud, nl, KernelType::CubicSpline, cloud.spacing},
                                                {OperatorKind::Laplacian, nullptr, nullptr, unknown});
    Field f(cloud.size()), g(cloud.size());
    for (Index i = 0; i < cloud.size(); ++i) {
      const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
      g[i] = std::sin(3 * x[0]) * std::exp(x[1]);
      f[i] = -8 * g[i];
    }
    sys = assemble(L, cloud, unknown, f, g);
  }
};

SolveReport run(const LinearSystem& sys, Eigen::VectorXd& x, const std::string& options = "") {
  SolverOptions o;
  o.type = SolverType::Petsc;
  o.petsc_options = options;
  return solve(sys, x, o);
}

// Restores an environment variable when it goes out of scope.
struct EnvVar {
  std::string name;
  explicit EnvVar(std::string n, const char* value) : name(std::move(n)) { ::setenv(name.c_str(), value, 1); }
  ~EnvVar() { ::unsetenv(name.c_str()); }
};
}  // namespace

TEST(Petsc, AgreesWithTheDirectSolverAndReportsWhatRan) {
  const System s(40);
  Eigen::VectorXd direct, amg;
  SolverOptions lu;
  lu.type = SolverType::UmfPack;
  ASSERT_TRUE(solve(s.sys, direct, lu).success);
  const SolveReport r = run(s.sys, amg);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.solver, "petsc fgmres+hypre(boomeramg)");
  EXPECT_EQ(r.reason, "converged_rtol");
  EXPECT_GT(r.iterations, 2);
  EXPECT_LT(r.iterations, 40);
  // The history has the initial residual and one entry per iteration, decreasing by rtol.
  ASSERT_EQ(r.residual_history.size(), static_cast<std::size_t>(r.iterations) + 1);
  EXPECT_LT(r.residual_history.back(), 1e-10 * r.residual_history.front());
  // Right preconditioning: the true residual is what the test saw.
  EXPECT_LT(r.residual, 1e-9);
  EXPECT_GT(r.seconds_setup, 0);
  EXPECT_LT((amg - direct).cwiseAbs().maxCoeff(), 1e-8 * direct.cwiseAbs().maxCoeff());
}

// 3D systems whose set-up serves one solve coarsen aggressively on AMG's first level (a third
// of the set-up, docs/solvers.md); a reused set-up (a flow's stages) and 2D keep the standard
// coarsening. The options say so, the solves show it (the same iterations as the options given
// by hand), and every form agrees with the direct solve.
TEST(Petsc, ThreeDimensionalDefaultsCoarsenAggressivelyOncePerSetup) {
  EXPECT_NE(default_petsc_options(3).find("-pc_hypre_boomeramg_agg_nl 1"), std::string::npos);
  EXPECT_EQ(default_petsc_options(3, true).find("agg_nl"), std::string::npos);
  EXPECT_EQ(default_petsc_options(2).find("agg_nl"), std::string::npos);
  const System s(12, "vrsph", 3);
  Eigen::VectorXd direct;
  SolverOptions lu;
  lu.type = SolverType::UmfPack;
  ASSERT_TRUE(solve(s.sys, direct, lu).success);
  const auto iterations = [&](bool reused, const std::string& extra) {
    SolverOptions o;
    o.type = SolverType::Petsc;
    o.dimension = 3;
    o.reused_setup = reused;
    o.petsc_options = extra;
    Eigen::VectorXd x;
    const SolveReport r = solve(s.sys, x, o);
    EXPECT_TRUE(r.success) << r.message;
    EXPECT_LT((x - direct).cwiseAbs().maxCoeff(), 1e-8 * direct.cwiseAbs().maxCoeff());
    return r.iterations;
  };
  const int once = iterations(false, ""), reused = iterations(true, "");
  EXPECT_EQ(once, iterations(true, "-pc_hypre_boomeramg_agg_nl 1"));
  EXPECT_EQ(reused, iterations(false, "-pc_hypre_boomeramg_agg_nl 0"));
  EXPECT_GT(once, reused);  // aggressive coarsening: more iterations, each cheaper
}

// The default preconditioner applies two V-cycles whose up-sweeps are hybrid Gauss-Seidel: fewer
// iterations than one Jacobi-smoothed V-cycle (about half at 10^5 and more unknowns: 10 against 19
// at 10^6, docs/solvers.md), the same solution. A caller's smoother for all sweeps covers the
// up-sweep too (PETSc applies relax_type_up after relax_type_all): given with one V-cycle it
// takes exactly the iterations of the same options spelt out sweep by sweep.
TEST(Petsc, DefaultsTakeTwoVCyclesWithGaussSeidelUpSweeps) {
  const std::string defaults = default_petsc_options(2);
  EXPECT_NE(defaults.find("-pc_hypre_boomeramg_max_iter 2"), std::string::npos);
  EXPECT_NE(defaults.find("-pc_hypre_boomeramg_relax_type_up SOR/Jacobi"), std::string::npos);
  EXPECT_EQ(default_petsc_options(2, false, false).find("max_iter"), std::string::npos);
  EXPECT_EQ(default_petsc_options(3, true, false).find("relax_type_up"), std::string::npos);
  const System s(100);
  Eigen::VectorXd direct;
  SolverOptions lu;
  lu.type = SolverType::UmfPack;
  ASSERT_TRUE(solve(s.sys, direct, lu).success);
  const auto iterations = [&](const std::string& options) {
    Eigen::VectorXd x;
    const SolveReport r = run(s.sys, x, options);
    EXPECT_TRUE(r.success) << options << ": " << r.message;
    EXPECT_LT((x - direct).cwiseAbs().maxCoeff(), 1e-8 * direct.cwiseAbs().maxCoeff()) << options;
    return r.iterations;
  };
  const int now = iterations("");
  const int one_jacobi_cycle = iterations("-pc_hypre_boomeramg_max_iter 1 -pc_hypre_boomeramg_relax_type_up Jacobi");
  EXPECT_LT(now, one_jacobi_cycle);
  for (const bool scaled : {true, false}) {  // SolverOptions::two_cycles off, or unscaled rows: one Jacobi cycle
    SolverOptions o;
    o.type = SolverType::Petsc;
    o.two_cycles = !scaled;
    o.scale_rows = scaled;
    o.balance_columns = false;
    SolverOptions same = o;
    same.petsc_options = "-pc_hypre_boomeramg_max_iter 1 -pc_hypre_boomeramg_relax_type_up Jacobi";
    Eigen::VectorXd x, y;
    EXPECT_EQ(solve(s.sys, x, o).iterations, solve(s.sys, y, same).iterations) << (scaled ? "two_cycles off" : "unscaled rows");
  }
  EXPECT_EQ(iterations("-pc_hypre_boomeramg_max_iter 1 -pc_hypre_boomeramg_relax_type_all Jacobi"), one_jacobi_cycle);
  {
    const EnvVar env("PETSC_OPTIONS", "-pc_hypre_boomeramg_relax_type_all Jacobi");
    EXPECT_EQ(iterations("-pc_hypre_boomeramg_max_iter 1"), one_jacobi_cycle) << "PETSC_OPTIONS' smoother too";
  }
  EXPECT_EQ(iterations("-pc_hypre_boomeramg_relax_type_all Jacobi -pc_hypre_boomeramg_relax_type_up SOR/Jacobi"), now)
      << "an up-sweep of the caller's own wins over their smoother for all sweeps";
}

// The rows weighted by the left null vector's estimate (SolverOptions::balance_columns, the
// default) change what AMG sees, not the solution: both forms agree with the direct solve, the
// true residual meets the tolerance, and the balanced one needs no more iterations (at 10^6
// perturbed particles it needs a fifth fewer: docs/solvers.md).
TEST(Petsc, BalancedColumnsKeepTheSolutionAndNeedNoMoreIterations) {
  const System s(100);
  Eigen::VectorXd direct, balanced, plain;
  SolverOptions lu;
  lu.type = SolverType::UmfPack;
  ASSERT_TRUE(solve(s.sys, direct, lu).success);
  SolverOptions o;
  o.type = SolverType::Petsc;
  ASSERT_TRUE(o.balance_columns) << "the default";
  const SolveReport on = solve(s.sys, balanced, o);
  o.balance_columns = false;
  const SolveReport off = solve(s.sys, plain, o);
  ASSERT_TRUE(on.success) << on.message;
  ASSERT_TRUE(off.success) << off.message;
  EXPECT_LT(on.residual, 1e-9);
  EXPECT_LE(on.iterations, off.iterations);
  EXPECT_LT((balanced - direct).cwiseAbs().maxCoeff(), 1e-8 * direct.cwiseAbs().maxCoeff());
  EXPECT_LT((plain - direct).cwiseAbs().maxCoeff(), 1e-8 * direct.cwiseAbs().maxCoeff());
}

TEST(Petsc, UserOptionsWinAndDoNotLeakIntoTheNextSolve) {
  const System s(24);
  Eigen::VectorXd x;
  const SolveReport cg = run(s.sys, x, "-ksp_type bcgs -pc_type jacobi");
  ASSERT_TRUE(cg.success) << cg.message;
  EXPECT_EQ(cg.solver, "petsc bcgs+jacobi");
  EXPECT_TRUE(cg.warnings.empty());
  const SolveReport next = run(s.sys, x);
  EXPECT_EQ(next.solver, "petsc fgmres+hypre(boomeramg)");
  {
    const EnvVar env("PETSC_OPTIONS", "-ksp_type bcgs");
    EXPECT_EQ(run(s.sys, x).solver, "petsc bcgs+hypre(boomeramg)");
    EXPECT_EQ(run(s.sys, x, "-ksp_type gmres").solver, "petsc gmres+hypre(boomeramg)") << "--petsc-options win";
  }
  // A misspelt option is reported, not ignored in silence.
  const SolveReport typo = run(s.sys, x, "-ksp_tipe cg");
  ASSERT_EQ(typo.warnings.size(), 1u);
  EXPECT_NE(typo.warnings[0].find("-ksp_tipe was given but not used"), std::string::npos);
}

TEST(Petsc, FailuresAreStatusesOrTypedErrorsWithPetscText) {
  const System s(24);
  Eigen::VectorXd x;
  EXPECT_THROW_MSG(run(s.sys, x, "-ksp_type nonsense"), ConfigError, "Unable to find requested KSP type nonsense");
  EXPECT_THROW_MSG(run(s.sys, x, "-pc_type nonsense"), ConfigError, "Unable to find requested PC type nonsense");
  const SolveReport stalled = run(s.sys, x, "-ksp_max_it 2");
  EXPECT_FALSE(stalled.success);
  EXPECT_EQ(stalled.reason, "diverged_its");
  EXPECT_NE(stalled.message.find("stopped without converging: diverged_its after 2 iterations"), std::string::npos);
  // After an error PETSc is still usable.
  EXPECT_TRUE(run(s.sys, x).success);
}

TEST(Petsc, MonitorSeesEveryIteration) {
  const System s(24);
  Eigen::VectorXd x;
  SolverOptions o;
  o.type = SolverType::Petsc;
  std::vector<int> seen;
  o.monitor = [&](int it, Real) { seen.push_back(it); };
  const SolveReport r = solve(s.sys, x, o);
  ASSERT_TRUE(r.success);
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(r.iterations) + 1);
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], static_cast<int>(k));
}

TEST(Petsc, AutoPicksDirectWhenSmallAndAmgWhenLarge) {
  EXPECT_EQ(resolve_auto(1000, 2), SolverType::UmfPack);
  EXPECT_EQ(resolve_auto(1000000, 2), SolverType::Petsc);
  EXPECT_EQ(resolve_auto(50000, 3), SolverType::Petsc);
  EXPECT_EQ(resolve_auto(1000000, 1), SolverType::UmfPack) << "1D is banded";
  EXPECT_EQ(resolve_auto(1000, 2, 500), SolverType::Petsc) << "explicit limit";
  const System s(24);
  Eigen::VectorXd x;
  SolverOptions o;  // auto is the default
  EXPECT_EQ(solve(s.sys, x, o).solver, "auto: umfpack");
  // Without a dimension the solver assumes 3D (row lengths no longer tell: VRSPH's 2D
  // rows are as short as 1D SPH's): the fastest-growing fill estimate, the smallest limit.
  EXPECT_EQ(direct_solver_bytes(s.sys.A, 0), direct_solver_bytes(s.sys.A, 3));
  EXPECT_EQ(resolve_auto(5000, 0), SolverType::Petsc);
  o.auto_direct_max = 10;
  EXPECT_EQ(solve(s.sys, x, o).solver, "auto: petsc fgmres+hypre(boomeramg)");
  EXPECT_EQ(parse_solver("petsc"), SolverType::Petsc);
  EXPECT_THROW_MSG(parse_solver("amg"), ConfigError, "known: auto, petsc");
}

// The assembly hands PETSc sorted rows without stored zeros (the diagonal always stays),
// and the same bits whatever the number of threads.
TEST(Petsc, AssembledRowsAreSortedSparseAndThreadIndependent) {
  const System s(40);
  const CsrMatrix& A = s.sys.A;
  for (Index d = 0; d < A.rows(); ++d) {
    bool diagonal = false;
    for (Index k = A.outerIndexPtr()[d]; k < A.outerIndexPtr()[d + 1]; ++k) {
      if (k > A.outerIndexPtr()[d]) {
        EXPECT_LT(A.innerIndexPtr()[k - 1], A.innerIndexPtr()[k]);
      }
      diagonal |= A.innerIndexPtr()[k] == d;
      EXPECT_TRUE(A.innerIndexPtr()[k] == d || A.valuePtr()[k] != 0);
    }
    EXPECT_TRUE(diagonal) << "row " << d;
  }
  // VRSPH's volumes are mostly zero: far fewer entries than neighbours.
  EXPECT_LT(static_cast<double>(A.nonZeros()) / static_cast<double>(A.rows()), 14.0);
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const System one(40);
  omp_set_num_threads(2);
  const System two(40);
  omp_set_num_threads(threads);
  ASSERT_EQ(one.sys.A.nonZeros(), two.sys.A.nonZeros());
  EXPECT_TRUE(std::equal(one.sys.A.valuePtr(), one.sys.A.valuePtr() + one.sys.A.nonZeros(), two.sys.A.valuePtr()));
  EXPECT_TRUE(std::equal(one.sys.A.innerIndexPtr(), one.sys.A.innerIndexPtr() + one.sys.A.nonZeros(),
                         two.sys.A.innerIndexPtr()));
  EXPECT_EQ(one.sys.b, two.sys.b);
#endif
}

TEST(Petsc, AutoFallsBackToTheDirectSolverWhenAmgDoesNotConverge) {
  // auto with AMG that cannot converge (one iteration allowed): the direct solver takes
  // over, says so, and the solution is the direct one.
  const System s(24);
  Eigen::VectorXd x_auto, x_direct;
  SolverOptions o;
  o.type = SolverType::Auto;
  o.auto_direct_max = 1;  // make auto pick PETSc for this small system
  o.dimension = 2;
  o.petsc_options = "-ksp_max_it 1";
  const SolveReport r = solve(s.sys, x_auto, o);
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.solver, "auto: umfpack after petsc (diverged_its)");
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.front().find("did not converge (diverged_its); solved with UMFPACK instead"), std::string::npos);
  SolverOptions d;
  d.type = SolverType::UmfPack;
  (void)solve(s.sys, x_direct, d);
  EXPECT_LT((x_auto - x_direct).cwiseAbs().maxCoeff(), 1e-12);
  // Asked for PETSc explicitly, the same failure is reported, not replaced.
  EXPECT_FALSE(run(s.sys, x_auto, "-ksp_max_it 1").success);
}

// PreparedSolver: set up once, then any number of right-hand sides, each solved as well as
// the one-shot solve() does; an iterative solver started from the solution stops at once.
TEST(PreparedSolver, ManyRightHandSidesForEverySolver) {
  const System s(24);
  Eigen::VectorXd reference;
  SolverOptions direct;
  direct.type = SolverType::UmfPack;
  ASSERT_TRUE(solve(s.sys, reference, direct).success);
  for (SolverType type : {SolverType::UmfPack, SolverType::SparseLU, SolverType::BiCGSTAB, SolverType::Petsc}) {
    SolverOptions o;
    o.type = type;
    o.dimension = 2;
    const PreparedSolver solver(s.sys.A, o);
    EXPECT_EQ(solver.size(), s.sys.size());
    EXPECT_NE(solver.solver().find(to_string(type)), std::string::npos) << solver.solver();
    for (Real scale : {1.0, -2.5, 1e-3}) {
      Eigen::VectorXd x;
      const SolveReport rep = solver.solve(scale * s.sys.b, x);
      ASSERT_TRUE(rep.success) << solver.solver() << ": " << rep.message;
      EXPECT_LT(rep.residual, 1e-8) << solver.solver();
      EXPECT_LT((x - scale * reference).norm(), 1e-6 * std::abs(scale) * reference.norm()) << solver.solver();
    }
    if (type == SolverType::Petsc) {
      Eigen::VectorXd x = reference;  // the answer as the initial guess: no iteration needed
      const SolveReport rep = solver.solve(s.sys.b, x);
      EXPECT_TRUE(rep.success);
      EXPECT_LE(rep.iterations, 1);
    }
  }
  SolverOptions automatic;
  automatic.dimension = 2;
  EXPECT_EQ(PreparedSolver(s.sys.A, automatic).solver(), "auto: umfpack");
}

TEST(PreparedSolver, BadRightHandSidesAndMatricesAreNamed) {
  const System s(10);
  const PreparedSolver solver(s.sys.A);
  Eigen::VectorXd x;
  EXPECT_THROW_MSG(solver.solve(Eigen::VectorXd::Ones(3), x), InputError, "right-hand side of size 3");
  Eigen::VectorXd b = s.sys.b;
  b[0] = std::nan("");
  EXPECT_THROW_MSG(solver.solve(b, x), InputError, "not finite");
  const CsrMatrix rect(3, 4);
  EXPECT_THROW_MSG(PreparedSolver p(rect), InputError, "not square");
  SolverOptions bad;
  bad.type = SolverType::Petsc;
  bad.petsc_options = "-ksp_type no_such_ksp";
  EXPECT_THROW(PreparedSolver p(s.sys.A, bad), ConfigError);
}

// The back-ends borrow the matrix: a moved PreparedSolver must still solve.
TEST(PreparedSolver, StillSolvesAfterAMove) {
  const System s(12);
  for (SolverType type : {SolverType::BiCGSTAB, SolverType::Petsc, SolverType::UmfPack}) {
    SolverOptions o;
    o.type = type;
    PreparedSolver first(s.sys.A, o);
    const PreparedSolver moved(std::move(first));
    Eigen::VectorXd x;
    const SolveReport rep = moved.solve(s.sys.b, x);
    EXPECT_TRUE(rep.success) << moved.solver() << ": " << rep.message;
    EXPECT_LT(rep.residual, 1e-8) << moved.solver();
  }
}
