// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The FEniCSx peer of the benchmarks (../shared/anchors/fenicsx_ex5.py): [QW] Example 5 with
// Lagrange Pk elements, PETSc CG + BoomerAMG, serial or on P ranks under mpirun, run as a
// child process in the same run as vrsph and on the same cores. Shared by `bench solve`
// and `bench accuracy`.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace vrsph::cli {

/// The peer's command-line options, the same in `bench solve` and `bench accuracy`.
struct AnchorOptions {
  std::string anchor;  ///< "" or fenicsx
  std::string degrees = "1";
  std::string script;
  int ranks = 0;
};
/// Adds --anchor, --anchor-degree, --anchor-ranks, --anchor-script to `cmd`; `what` says
/// what --anchor does in this command.
void add_anchor_options(CLI::App& cmd, AnchorOptions& o, const std::string& what);
/// A peer option without --anchor is a ConfigError (it would be silently ignored).
void reject_peer_options_without_peer(const CLI::App& cmd, const AnchorOptions& o);

/// Which nodes the peer solves on.
enum class AnchorMesh {
  Structured,    ///< its n x n (x n) lattice split into simplices
  OwnPerturbed,  ///< its own perturbed node set (same distribution as ours, numpy RNG), Delaunay
  SamePoints     ///< exactly our cloud's points (--points; Delaunay; P1 and one rank only)
};
std::string to_string(AnchorMesh mesh);

struct AnchorSetup {
  std::string script;  ///< fenicsx_ex5.py
  int dim = 2;
  int ranks = 1;  ///< mpirun -np ranks (1: no mpirun)
};

struct AnchorRun {
  int degree = 1, cells = 0;  ///< Pk, cells per direction
  long long nodes = 0;        ///< global degrees of freedom (boundary included)
  double seconds_total = 0;   ///< mesh + assembly + solve, as the peer times them (imports excluded)
  double error_inf = 0;       ///< max nodal error over the unknowns
  int iterations = 0;
  double peak_bytes = 0;      ///< summed peak resident memory of the peer's processes (0: unknown)
  AnchorMesh mesh = AnchorMesh::Structured;
};

/// --anchor-script, else $VRSPH_ANCHOR_DIR/fenicsx_ex5.py, else ../shared/anchors next to
/// the source tree; throws IoError if the file does not exist.
std::string fenicsx_script(const std::string& option);
/// The peer's ranks: 0 = vrsph's threads; more than the machine's cores is a ConfigError
/// (the comparison is on the same cores), as is mpirun missing for more than one.
int anchor_ranks(int requested);
/// The peer's set-up from its options: the ranks checked first (a ConfigError, whatever the
/// script), then the script (IoError if it does not exist).
AnchorSetup anchor_setup(const AnchorOptions& o, int dim);
/// Pk degrees 1..3 from "1,2,3"; ConfigError otherwise.
std::vector<int> parse_anchor_degrees(const std::string& text);
/// Cells per direction that give Pk about the nodes of our n-interval lattice:
/// round(n / k), at least 1 (k n/k + 1 nodes per direction).
int anchor_cells(int n, int degree);
/// The mesh the peer can use for our cloud: our own points where it can mesh them (2D
/// perturbed, P1, one rank), else its own perturbed set (2D, one rank), else its lattice.
AnchorMesh anchor_mesh(const AnchorSetup& setup, bool perturbed, int degree);

/// Runs the peer once (one JSON line). points_csv: our cloud for AnchorMesh::SamePoints.
/// The first call of a (degree, dim) compiles its forms inside the peer's timed region:
/// warm_up_anchor first. Throws IoError naming the run when the peer fails or prints no result.
AnchorRun run_anchor(const AnchorSetup& setup, int degree, int cells, AnchorMesh mesh,
                     const std::string& points_csv = "");
/// One tiny run per degree, so that form compilation stays out of the timed runs.
void warm_up_anchor(const AnchorSetup& setup, const std::vector<int>& degrees);

}  // namespace vrsph::cli
