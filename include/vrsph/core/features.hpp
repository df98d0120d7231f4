// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The optional parts of this build (PETSc, MPI, CGAL, Clp, SuiteSparse, muParser, VTK XML
// reading, JSON reading, TOML problem files, OpenMP; cmake/vrsph_parts.cmake) and the one way a feature of a missing part fails.
#include <string>
#include <string_view>
#include <vector>
#include <vrsph/core/error.hpp>

namespace vrsph {

/// A feature was asked of a part vrsph was built without. A ConfigError (CLI exit code 2):
/// the build's configuration, not the input, is what lacks it.
class FeatureUnavailable : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

struct Part {
  std::string_view name;      ///< "PETSC": the CMake option is VRSPH_WITH_<name>
  std::string_view what;      ///< what it brings
  std::string_view licence;   ///< of the part itself (a GPL part binds the binaries it is linked into)
  std::string_view packages;  ///< the Debian packages that provide it
  bool built = false;
};

/// Every optional part, built or not, in a fixed order.
const std::vector<Part>& parts();
/// Whether this build has the part (`name` as in Part::name; unknown names: false).
bool built_with(std::string_view name);
/// The version of the library, "0.2.0" (the CMake project version).
std::string_view version();
/// Throws FeatureUnavailable unless the part is built: "<feature> needs <what>: vrsph was
/// built without it; rebuild with -DVRSPH_WITH_<name>=ON (Debian: apt-get install <packages>)".
void require_part(std::string_view name, std::string_view feature);

}  // namespace vrsph
