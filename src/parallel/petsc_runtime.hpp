// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: PETSc (and MPI) started once per process, on first use, by the solver back-end
// or by Communicator::world(). Shared so that both start it the same way.
namespace vrsph::detail {
/// Starts PETSc unless it runs already; throws ConfigError if it cannot start.
void start_petsc();
}  // namespace vrsph::detail
