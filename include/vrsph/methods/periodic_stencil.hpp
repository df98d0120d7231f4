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
/// The same from a minimum-image neighbour list over the N particles (find_neighbours on the
/// periodic cloud, or neighbour_list_from a list of one's own): the rows of the images are that
/// list moved by their shifts, cut where the images end, as the search of the images cuts them.
/// InputError for a list of another size or without shift codes.
Stencil periodic_stencil(const Method& method, const PointCloud& cloud, const NeighbourList& neighbours,
                         KernelType kernel, Real spacing, const StencilRequest& request);

}  // namespace vrsph
