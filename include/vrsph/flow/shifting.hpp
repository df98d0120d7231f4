// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Particle shifting for Lagrangian flows: after a step, every particle moves by a small δr_i
// away from where its neighbours crowd, and its velocity follows by a first-order Taylor
// step, u_i + (∇u)_i · δr_i (with the flow's gradient). Off by default (FlowOptions).
//  - xu    (Xu, Stansby & Laurence 2009, eq. (35)): δr_i = β r̄_i² U dt Σ_j x_ij / r_ij³,
//          x_ij = x_i - x_j, r̄_i the mean neighbour distance, U the largest speed, β = 0.04;
//  - lind  (Lind, Xu, Stansby & Rogers 2012, Fickian): δr_i = -A ℓ |u_i| dt Σ_j V ∇W_ij,
//          ℓ the smoothing length (the kernel's support over its support-per-length ratio),
//          V = dx^d, A = 2 (they report stable runs for A from 1 to 6).
// Both read only the neighbour list (periodic images through its shifts). Neither bounds its
// δr: Xu's Σ x_ij / r_ij³ grows without limit as two particles meet (a dam break's impact on
// the far wall shifted a particle by 7 spacings in one step, docs/free_surface.md), so no
// particle moves more than `max_shift` spacings in one call (its direction kept).
#include <string>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/method.hpp>

namespace vrsph {

enum class Shifting { None, Xu, Lind };
/// "none" | "xu" | "lind"; ConfigError otherwise.
Shifting parse_shifting(const std::string& name);
std::string to_string(Shifting s);

struct ShiftingOptions {
  Shifting kind = Shifting::None;
  Real coefficient = 0;  ///< β (xu) or A (lind); 0: the published default (0.04, 2)
  /// The largest shift of one call, in particle spacings (longer ones are scaled down to it); 0:
  /// unbounded, as published. A quarter spacing binds only where particles nearly meet.
  Real max_shift = 0.25;
};

/// δr_i for every particle of `disc` (its cloud, neighbour list, kernel and spacing) after a
/// step dt of the velocity u (N x d), each at most options.max_shift spacings long. ConfigError
/// for a negative or non-finite coefficient or limit.
std::vector<Vec3> shifting_displacements(const Discretisation& disc, const ShiftingOptions& options,
                                         const Eigen::MatrixXd& u, Real dt);

}  // namespace vrsph
