#pragma once
// Internal: the solver back-ends behind vrsph::solve. Each fills x and the report's
// success, reason, message, iterations, history and set-up time; the dispatcher
// (solver.cpp) checks memory up front and measures the true residual afterwards.
#include <vrsph/solve/solver.hpp>

namespace vrsph::detail {

/// The dimension the solver assumes when the caller gave none: 3, the fastest-growing LU
/// fill-in estimate and the smallest direct-solve limit of `auto`. (It cannot be read off the
/// row lengths: with exact zeros dropped, a 2D VRSPH row has ~10 entries, a 1D SPH row ~7.)
inline int assumed_dimension(int dimension) { return dimension > 0 ? dimension : 3; }

void solve_eigen(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep);
void solve_petsc(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep);

}  // namespace vrsph::detail
