// SPDX-License-Identifier: BSD-3-Clause
// A build without PETSc (VRSPH_WITH_PETSC=OFF): the PETSc back-end is refused with
// FeatureUnavailable; `auto` never picks it there (solver.cpp).
#include <vrsph/core/features.hpp>
#include "backends.hpp"

namespace vrsph::detail {

std::unique_ptr<Backend> prepare_petsc(const CsrMatrix&, const SolverOptions&) {
  require_part("PETSC", "--solver petsc");
  return nullptr;  // not reached: the part is not built
}

}  // namespace vrsph::detail
