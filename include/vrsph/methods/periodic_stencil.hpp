// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A method's stencil on a cloud whose box is periodic (Domain::periodic): its rows are built
// on the cloud extended by the periodic images within the rows' reach (neighbours/periodic.hpp),
// so every method runs unchanged, and the images' columns are folded onto their originals.
#include <vrsph/methods/method.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

/// Rows over the N particles of `cloud`, columns over the same N. The request's fields
/// (coefficient, its gradient, mobility, rows) are over the N particles. `search` gives the
/// support (radius or per-particle radii); its periodic wrapping is done here. Throws as
/// find_neighbours and Method::build do (a period not larger than 2 h: InputError).
Stencil periodic_stencil(const Method& method, const PointCloud& cloud, const SearchParams& search, KernelType kernel,
                         Real spacing, const StencilRequest& request);

}  // namespace vrsph
