// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Flow through heterogeneous media against a finite-volume reference: [SPE] §5.3 "SPE10"
// (METHODS §5.3, R18).
//
// -div(K grad u) = 0 on [0,1]^d with a diagonal permeability K on an n^d cell grid, u = 1
// on the inlet face (flow axis = 0), u = 0 on the outlet face, no flow elsewhere. The
// particles are the cell centres plus boundary particles on the faces (layout B); each
// particle takes the permeability of its cell. Every method is compared with the TPFA
// solution on the same grid (problem/tpfa.hpp), cell by cell.
//
// Problems (all substitutes for SPE10, which is not available offline, unless the user
// reads the real file):
//   spe-channel    channelised field, contrast 1e6 by default (channel_permeability)
//   spe-lognormal  log-normal field with a correlation length (lognormal_permeability)
//   spe10          a field read from a file in the spe_perm.dat layout (read_permeability)
//
// An isotropic field (k_x = k_y = k_z in every cell) is given to every method as the scalar
// coefficient a = k; an anisotropic one as the tensor K to the methods that take one, and as
// the harmonic mean d / Σ_k 1/k_k to the others (column `coefficient`). The pair
// coefficient of the flux-form schemes is the method option `mean` (methods/pair_mean.hpp).
//
// The optional Krylov study ([SPE] Figs. 11-12) solves every method's assembled system
// again with restarted GMRES (PETSc, right preconditioning so that the residual is the
// true one, zero initial guess) and each requested preconditioner, recording the
// iteration count and the relative residual history.
#include <functional>
#include <map>
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/problem/permeability.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

/// spe-channel, spe-lognormal and spe10.
bool is_heterogeneous_problem(const std::string& problem);

struct KrylovStudyOptions {
  std::vector<std::string> preconditioners;  ///< none | jacobi | ilu (ILU(0)) | amg (BoomerAMG); empty: no study
  int restart = 30;
  Real rtol = 1e-8;                          ///< on the true relative residual ||b - A x|| / ||b||
  int max_iterations = 3000;
};

struct HeterogeneousStudyParams {
  std::string problem = "spe-channel";
  int dim = 2;
  int n = 60;                                ///< cells per axis of a generated field
  /// The field to use (spe10: read by the caller); empty: generated from the options below.
  PermeabilityField field;
  ChannelFieldOptions channel;
  LognormalFieldOptions lognormal;
  std::vector<std::string> methods{"m-sph", "s-sph", "vrsph", "tpfa"};
  std::map<std::string, MethodOptions> method_options;
  KernelType kernel = KernelType::CubicSplineSPE;
  Real support_factor = 2.002;               ///< support radius / dx ([SPE]: 2 f with f = 1.001)
  int flow_axis = 1;
  SolverOptions solver;
  Real infeasible_tolerance = 1e-6;
  KrylovStudyOptions krylov;
  bool keep_fields = false;                  ///< keep the cloud and every method's solution
  std::function<void(const std::string&, double)> progress;
  /// Distributed: each particle method's solve() runs over these ranks (every rank builds
  /// the field and passes an equal slice of the particles); the TPFA reference is solved
  /// on every rank alike (serial), the Krylov study (krylov) is refused. The result is the
  /// same on every rank.
  Communicator communicator;
};

struct HeterogeneousRun {
  std::string method;
  std::string coefficient;                   ///< scalar | tensor | harmonic (TPFA: its face permeabilities)
  Index particles = 0, unknowns = 0;
  Real h = 0;
  Real error_rel_max = 0;                    ///< max over cells |u - u_TPFA| / |u_TPFA| ([SPE] (95) at its worst)
  Real error_rel_rms = 0;                    ///< (95): root mean square of the same
  Real error_abs_max = 0;                    ///< max |u - u_TPFA| (the pressure drop is 1)
  /// The rate from inlet to outlet: TPFA's outlet flux; for the particle methods the pair
  /// fluxes V_I L_IJ (u_I - u_J) crossing a cross-section, averaged over all cross-sections.
  Real outlet_flux = 0;
  /// (max - min) / mean of the rates through the cross-sections between particle layers
  /// (TPFA: |inlet - outlet| / outlet): 0 for a conservative scheme.
  Real flux_spread = 0;
  Real flux_error_rel = 0;                   ///< |outlet - outlet_TPFA| / outlet_TPFA
  bool m_matrix = false;
  Index negative_transmissibilities = 0;
  Real min_u = 0, max_u = 0;                 ///< over the unknowns
  bool monotone = false;                     ///< min_u >= 0 and max_u <= 1 (to 1e-9): discrete maximum principle
  Index infeasible = 0;
  SolveReport solve;
  double seconds = 0;
  Field u;                                   ///< keep_fields: at every particle (TPFA: empty)
};

struct KrylovRun {
  std::string method, preconditioner;
  int iterations = 0;
  bool converged = false;
  std::string reason;
  Real residual = 0;                         ///< true relative residual at the end
  double seconds = 0;
  std::vector<Real> history;                 ///< ||r_k|| / ||b|| per iteration (x_0 = 0)
};

struct HeterogeneousStudyResult {
  HeterogeneousStudyParams params;           ///< as run (field filled in)
  std::vector<HeterogeneousRun> runs;
  std::vector<KrylovRun> krylov;
  Field reference;                           ///< TPFA pressure per cell
  PointCloud cloud;                          ///< keep_fields
  std::vector<std::string> warnings;
};

/// Throws ConfigError (unknown problem, method or preconditioner, bad settings),
/// InputError (an invalid field) and NumericalError (a failed solve).
HeterogeneousStudyResult run_heterogeneous_study(const HeterogeneousStudyParams& params);

Table to_table(const HeterogeneousStudyResult& result);
/// One row per (method, preconditioner) of the Krylov study.
Table krylov_table(const HeterogeneousStudyResult& result);
/// The residual histories as a long table: method, preconditioner, iteration, residual.
Table krylov_history_table(const HeterogeneousStudyResult& result);
/// The field statistics and settings, as a JSON object.
Json metadata_json(const HeterogeneousStudyResult& result);

}  // namespace vrsph
