// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: vrsph::solve for BvpSolveOptions::communicator with more than one rank.
#include <vrsph/problem/boundary_value_problem.hpp>

namespace vrsph::detail {
BvpSolution solve_distributed(const BoundaryValueProblem& chunk, const BvpSolveOptions& options);
}
