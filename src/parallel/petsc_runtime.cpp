// SPDX-License-Identifier: BSD-3-Clause
// PETSc started once per process: no signal handler, no .petscrc, errors as return codes.
#include <petscsys.h>

#include <cstdlib>
#include <vrsph/core/error.hpp>
#include "petsc_runtime.hpp"

namespace vrsph::detail {
namespace {
void finalise_petsc() {
  PetscBool done = PETSC_FALSE;
  if (PetscFinalized(&done) == 0 && !done) PetscFinalize();
}

}  // namespace

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


}  // namespace vrsph::detail
