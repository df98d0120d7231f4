#pragma once
// Internal: the solver back-ends behind vrsph::solve. Each fills x and the report's
// success, reason, message, iterations, history and set-up time; the dispatcher
// (solver.cpp) checks memory up front and measures the true residual afterwards.
#include <vrsph/solve/solver.hpp>

namespace vrsph::detail {

/// A guess of the geometry's dimension from the nonzeros per row of a particle
/// Laplacian at h = 3 dx (1D ~ 7, 2D ~ 29, 3D ~ 120), when the caller did not say.
inline int dimension_from_row_length(double per_row) { return per_row <= 15 ? 1 : per_row <= 50 ? 2 : 3; }

void solve_eigen(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep);
void solve_petsc(const LinearSystem& sys, Eigen::VectorXd& x, const SolverOptions& o, SolveReport& rep);

}  // namespace vrsph::detail
