// SPDX-License-Identifier: BSD-3-Clause
// Voronoi deviation d_N by LP (63) (see analysis/voronoi_deviation.hpp).
#include <vrsph/config.hpp>
#include <vrsph/core/features.hpp>
#if VRSPH_HAVE_CLP
#include <coin/Clp_C_Interface.h>
#else
using CoinBigIndex = int;  // (the LP's assembly compiles in every build; solve_block refuses first)
#endif
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <exception>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <vrsph/analysis/voronoi_deviation.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::max();  // Clp's unbounded

// The transport a: a_ii per particle and a_ij per slot of the pair list (i's row, j != i).
struct Transport {
  std::vector<Real> self;
  std::vector<Real> pair;
};

struct Problem {
  NeighbourList pairs;       // pairs within the radius, distances cached
  std::vector<Real> cells;   // |sigma_i| (scaled)
  std::vector<Real> volumes; // V_i (scaled)
  Real length_scale = 1;     // lengths in the LP are r / length_scale (dx)
  Real deviation_coefficient(std::size_t i, Real r) const { return cells[i] > 0 ? r / length_scale / cells[i] : 0; }
};

struct LpSize {
  Index variables = 0, constraints = 0;
};

// LP (63) of one block in Clp's column form. Rows: [0,n) supply, [n,2n) demand, [2n,3n)
// deviation (<= -fixed); columns: each member's a_ii, then its a_ij with j in the block,
// and last q (cost 1).
struct BlockLp {
  int n = 0;
  std::vector<Real> row_lo, row_hi, fixed;
  std::vector<CoinBigIndex> start{0};
  std::vector<int> index;
  std::vector<double> value, cost, col_lo, col_hi;
  std::vector<Index> slot_of_column;  // -1: a_ii

  void add_column(int row_supply, int row_demand, double dev_i, int row_i, double dev_j, int row_j) {
    index.push_back(row_supply), value.push_back(1);
    index.push_back(n + row_demand), value.push_back(1);
    if (dev_i > 0) index.push_back(2 * n + row_i), value.push_back(dev_i);
    if (dev_j > 0) index.push_back(2 * n + row_j), value.push_back(dev_j);
    start.push_back(static_cast<CoinBigIndex>(index.size()));
    cost.push_back(0), col_lo.push_back(0), col_hi.push_back(kInfinity);
  }
};

// The block's columns; what each member exchanges with particles outside the block (fixed
// in `t`) leaves its supply and demand and enters its deviation row as a constant.
BlockLp block_columns(const Problem& p, const std::vector<Index>& members, const std::vector<Index>& block_of,
                      Index block, const Transport& t) {
  BlockLp lp;
  const int n = lp.n = static_cast<int>(members.size());
  std::vector<int> local(p.cells.size(), -1);
  for (int k = 0; k < n; ++k) local[static_cast<std::size_t>(members[static_cast<std::size_t>(k)])] = k;
  lp.row_lo.resize(static_cast<std::size_t>(3 * n));
  lp.row_hi.resize(static_cast<std::size_t>(3 * n));
  lp.fixed.assign(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    const auto si = static_cast<std::size_t>(members[static_cast<std::size_t>(k)]);
    lp.row_lo[static_cast<std::size_t>(k)] = p.cells[si];
    lp.row_lo[static_cast<std::size_t>(n + k)] = p.volumes[si];
  }
  for (int k = 0; k < n; ++k) {
    const Index i = members[static_cast<std::size_t>(k)];
    const auto si = static_cast<std::size_t>(i);
    lp.add_column(k, k, 0, k, 0, k);
    lp.slot_of_column.push_back(-1);
    const auto nbr = p.pairs.of(i);
    const auto dist = p.pairs.distances_of(i);
    const Index first = p.pairs.offsets[si];
    for (std::size_t s = 0; s < nbr.size(); ++s) {
      const auto sj = static_cast<std::size_t>(nbr[s]);
      const Real r = dist[s];
      if (block_of[sj] == block) {
        lp.add_column(k, local[sj], p.deviation_coefficient(si, r), k, p.deviation_coefficient(sj, r), local[sj]);
        lp.slot_of_column.push_back(first + static_cast<Index>(s));
        continue;
      }
      // A fixed crossing pair, in either direction: remove it from the supply/demand.
      const Real out = t.pair[static_cast<std::size_t>(first) + s];  // a_ij, i inside
      lp.row_lo[static_cast<std::size_t>(k)] -= out;
      lp.fixed[static_cast<std::size_t>(k)] += out * p.deviation_coefficient(si, r);
      const auto back = p.pairs.of(static_cast<Index>(sj));
      const auto pos = std::find(back.begin(), back.end(), i) - back.begin();
      const Real in = t.pair[static_cast<std::size_t>(p.pairs.offsets[sj] + pos)];  // a_ji
      lp.row_lo[static_cast<std::size_t>(n + k)] -= in;
      lp.fixed[static_cast<std::size_t>(k)] += in * p.deviation_coefficient(si, r);
    }
  }
  return lp;
}

// The rows' bounds: supply and demand balanced, equalities, the deviation rows; and q.
void block_rows(BlockLp& lp, const std::vector<Index>& members) {
  const int n = lp.n;
  auto& lo = lp.row_lo;
  auto& hi = lp.row_hi;
  // Round-off in the crossing flows (and in sum V = sum |sigma|) leaves the block's supply and
  // demand apart by ~1e-8 of a cell: more than the LP's feasibility tolerance. Scale the
  // demands onto the supply (a relative change of that size), else the LP is "infeasible".
  Real supply = 0, demand = 0;
  for (int k = 0; k < n; ++k) supply += std::max(0.0, lo[static_cast<std::size_t>(k)]), demand += std::max(0.0, lo[static_cast<std::size_t>(n + k)]);
  check<NumericalError>(std::abs(supply - demand) <= 1e-6 * (supply + 1), "Voronoi deviation: a block's cells and volumes "
                        "differ by ", supply - demand, " mean cells after the crossing flows");
  if (demand > 0)
    for (int k = 0; k < n; ++k) lo[static_cast<std::size_t>(n + k)] *= supply / demand;
  // q: one column with -1 in every deviation row.
  for (int k = 0; k < n; ++k) lp.index.push_back(2 * n + k), lp.value.push_back(-1);
  lp.start.push_back(static_cast<CoinBigIndex>(lp.index.size()));
  lp.cost.push_back(1), lp.col_lo.push_back(0), lp.col_hi.push_back(kInfinity);
  for (int k = 0; k < n; ++k) {
    const auto sk = static_cast<std::size_t>(k), dk = static_cast<std::size_t>(n) + sk;
    for (std::size_t r : {sk, dk})
      check<NumericalError>(lo[r] > -1e-9, "Voronoi deviation: the flows between blocks exceed particle ",
                            members[sk], "'s ", r == sk ? "cell" : "volume",
                            "; use a larger pair radius or a larger --dn-direct-limit");
    lo[sk] = std::max(lo[sk], 0.0), lo[dk] = std::max(lo[dk], 0.0);
    hi[sk] = lo[sk], hi[dk] = lo[dk];
    lo[static_cast<std::size_t>(2 * n) + sk] = -kInfinity;
    hi[static_cast<std::size_t>(2 * n) + sk] = -lp.fixed[sk];
  }
}

// LP (63) for the particles `members` (all of one block), with what the particles outside
// the block exchange with them fixed in `t`: the block's rows and columns get the
// remaining supply and demand, and the fixed pairs' share of the deviation as a constant.
// Writes the block's a_ij (both ends inside) into `t`.
LpSize solve_block(const Problem& p, const std::vector<Index>& members, const std::vector<Index>& block_of, Index block,
                   Transport& t, Real max_seconds) {
  // A build without Clp refuses before assembling anything (--dn-method flow needs no LP).
  require_part("CLP", "the Voronoi deviation's linear program (--dn-method lp; --dn-method flow needs no LP)");
  BlockLp b = block_columns(p, members, block_of, block, t);
  block_rows(b, members);
  const int n = b.n;
#if VRSPH_HAVE_CLP
  std::unique_ptr<Clp_Simplex, void (*)(Clp_Simplex*)> lp(Clp_newModel(), Clp_deleteModel);
  Clp_setLogLevel(lp.get(), 0);
  Clp_setMaximumSeconds(lp.get(), max_seconds);
  Clp_setPrimalTolerance(lp.get(), 1e-9);  // rows are O(1) (mean cell 1): balances to ~1e-9
  const auto cols = static_cast<int>(b.cost.size());
  Clp_loadProblem(lp.get(), cols, 3 * n, b.start.data(), b.index.data(), b.value.data(), b.col_lo.data(), b.col_hi.data(),
                  b.cost.data(), b.row_lo.data(), b.row_hi.data());
  Clp_initialSolve(lp.get());
  const int status = Clp_status(lp.get());
  if (status != 0) {
    const char* why = status == 1   ? "infeasible"
                      : status == 3 ? "stopped at its time or iteration limit"
                                    : "failed";
    throw NumericalError(detail::concat("Voronoi deviation: LP (63) ", why, " (Clp status ", status, ", ", cols,
                                        " variables, ", 3 * n, " constraints)"));
  }
  const double* a = Clp_getColSolution(lp.get());
  // Each member's a_ii column comes first in its run of columns.
  for (int c = 0, k = -1; c + 1 < cols; ++c) {
    const Index slot = b.slot_of_column[static_cast<std::size_t>(c)];
    if (slot < 0)
      t.self[static_cast<std::size_t>(members[static_cast<std::size_t>(++k)])] = std::max(0.0, a[c]);
    else
      t.pair[static_cast<std::size_t>(slot)] = std::max(0.0, a[c]);
  }
  return {cols, 3 * n};
#else
  (void)max_seconds, (void)t, (void)n;
  return {};  // not reached: refused at the start
#endif
}

// phi with L phi = E for the weighted graph Laplacian L given by `trip` (diagonal and
// off-diagonal entries; sum E = 0): the constant is pinned by phi_0 = 0. A residual left
// means a disconnected graph: NumericalError naming `disconnected`.
Eigen::VectorXd graph_potential(Index n, std::vector<Eigen::Triplet<Real>> trip, const Eigen::Ref<const Eigen::VectorXd>& E,
                                const char* disconnected) {
  trip.emplace_back(0, 0, 1.0);
  Eigen::SparseMatrix<Real> L(n, n);
  L.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>> ldlt(L);
  Eigen::VectorXd phi = ldlt.solve(E);
  L.coeffRef(0, 0) -= 1.0;
  check<NumericalError>(ldlt.info() == Eigen::Success && (L * phi - E).norm() <= 1e-8 * (E.norm() + 1),
                        "Voronoi deviation: ", disconnected);
  return phi;
}

// Potential flow on the block graph: per crossing pair (i in k, j in l) the transport
// a_ij = c_ij max(0, phi_k - phi_l), c_ij = min(|sigma_i|, |sigma_j|) (scaled: ~1), so that
// small cells (at the domain's edge) are not asked to pass as much as full ones; the
// imbalance E_k = sum_k (|sigma_i| - V_i) leaves block k: L phi = E with L the graph
// Laplacian weighted by the sums of c_ij over crossing pairs.
void crossing_flows(const Problem& p, const std::vector<Index>& block_of, Index nblocks, Transport& t) {
  std::vector<Real> imbalance(static_cast<std::size_t>(nblocks), 0);
  std::map<std::pair<Index, Index>, Real> weight;
  auto capacity = [&p](std::size_t i, std::size_t j) { return std::min(p.cells[i], p.cells[j]); };
  for (std::size_t i = 0; i < p.cells.size(); ++i) {
    imbalance[static_cast<std::size_t>(block_of[i])] += p.cells[i] - p.volumes[i];
    for (Index j : p.pairs.of(static_cast<Index>(i)))
      if (block_of[static_cast<std::size_t>(j)] != block_of[i])  // (k,l) from i's list, (l,k) from j's
        weight[{block_of[i], block_of[static_cast<std::size_t>(j)]}] += capacity(i, static_cast<std::size_t>(j));
  }
  std::vector<Eigen::Triplet<Real>> trip;
  for (const auto& [kl, w] : weight) {
    trip.emplace_back(kl.first, kl.first, w);
    trip.emplace_back(kl.first, kl.second, -w);
  }
  const Eigen::VectorXd phi = graph_potential(nblocks, std::move(trip), Eigen::Map<const Eigen::VectorXd>(imbalance.data(), nblocks),
                                              "the block graph is disconnected (blocks without pairs between them); use "
                                              "a larger pair radius or --dn-direct-limit");
  for (std::size_t i = 0; i < p.cells.size(); ++i) {
    const auto nbr = p.pairs.of(static_cast<Index>(i));
    for (std::size_t s = 0; s < nbr.size(); ++s) {
      const auto j = static_cast<std::size_t>(nbr[s]);
      const Index k = block_of[i], l = block_of[j];
      if (k != l) t.pair[static_cast<std::size_t>(p.pairs.offsets[i]) + s] = capacity(i, j) * std::max(0.0, phi[k] - phi[l]);
    }
  }
}

// A feasible transport without an LP: a potential flow over the pairs. a_ij = c_ij max(0,
// phi_i - phi_j) and a_ii = |sigma_i| - sum_j a_ij, with L phi = |sigma| - V (L the graph
// Laplacian weighted by c_ij). Every row sum is |sigma_i| and every column sum V_i (the net
// inflow is -(L phi)_i), so it is a decomposition of [IM] (6) and its deviation an upper
// bound on d_N; it is not minimised. c_ij = min(|sigma_i|, |sigma_j|) / (r_ij / dx)^3:
// small cells pass little, and the flow prefers short pairs (measured on the [IM] sets:
// within 1.08-1.24 of the LP's bound; weights r^0, r^-1, r^-2, r^-4, r^-6 did worse).
// False when some cell would have to pass on more than itself (a_ii < 0).
bool potential_flow(const Problem& p, Transport& t) {
  const auto n = static_cast<Index>(p.cells.size());
  const auto conductance = [&p](Index i, std::size_t s) {
    const auto j = static_cast<std::size_t>(p.pairs.of(i)[s]);
    const Real r = p.pairs.distances_of(i)[s] / p.length_scale;
    return std::min(p.cells[static_cast<std::size_t>(i)], p.cells[j]) / (r * r * r);
  };
  std::vector<Eigen::Triplet<Real>> trip;
  Eigen::VectorXd E(n);
  for (Index i = 0; i < n; ++i) {
    E[i] = p.cells[static_cast<std::size_t>(i)] - p.volumes[static_cast<std::size_t>(i)];
    const auto nbr = p.pairs.of(i);
    for (std::size_t s = 0; s < nbr.size(); ++s) {  // (i,j) from i's list, (j,i) from j's
      const Real c = conductance(i, s);
      trip.emplace_back(i, i, c);
      trip.emplace_back(i, nbr[s], -c);
    }
  }
  const Eigen::VectorXd phi = graph_potential(n, std::move(trip), E, "the pair graph is disconnected (particles without "
                                              "pairs between them); use a larger pair radius");
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const auto nbr = p.pairs.of(i);
    Real out = 0;
    for (std::size_t s = 0; s < nbr.size(); ++s) {
      const Real a = conductance(i, s) * std::max(0.0, phi[i] - phi[nbr[s]]);
      t.pair[static_cast<std::size_t>(p.pairs.offsets[si]) + s] = a;
      out += a;
    }
    t.self[si] = p.cells[si] - out;
    if (t.self[si] < -1e-12) return false;
    t.self[si] = std::max(t.self[si], 0.0);
  }
  return true;
}

std::vector<Index> spatial_blocks(const PointCloud& cloud, Index target, Index& nblocks) {
  Vec3 lo = cloud.positions[0], hi = lo;
  for (const auto& x : cloud.positions) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const int d = cloud.dim;
  const auto per_axis = static_cast<Index>(std::max(1.0, std::round(std::pow(static_cast<Real>(cloud.size()) / static_cast<Real>(target), 1.0 / d))));
  std::vector<Index> block(cloud.positions.size());
  for (std::size_t i = 0; i < block.size(); ++i) {
    Index b = 0;
    for (int k = d - 1; k >= 0; --k) {
      const Real u = hi[k] > lo[k] ? (cloud.positions[i][k] - lo[k]) / (hi[k] - lo[k]) : 0;
      b = b * per_axis + std::min(per_axis - 1, static_cast<Index>(u * static_cast<Real>(per_axis)));
    }
    block[i] = b;
  }
  // Renumber the non-empty blocks 0..nblocks-1.
  std::vector<Index> id(static_cast<std::size_t>(std::pow(per_axis, d)), -1);
  nblocks = 0;
  for (auto& b : block) {
    if (id[static_cast<std::size_t>(b)] < 0) id[static_cast<std::size_t>(b)] = nblocks++;
    b = id[static_cast<std::size_t>(b)];
  }
  return block;
}

}  // namespace

DeviationMethod parse_deviation_method(const std::string& name) {
  if (name == "auto") return DeviationMethod::Auto;
  if (name == "lp") return DeviationMethod::Lp;
  if (name == "flow") return DeviationMethod::Flow;
  throw ConfigError("unknown d_N method '" + name + "' (known: auto, lp, flow)");
}

namespace {
// The LP's data in scaled units (mean cell 1; lengths stay as they are, the LP's rows are
// then O(1)), after checking the volumes against the cells.
Problem scaled_problem(const PointCloud& cloud, std::span<const Real> volumes, std::span<const Real> cells,
                       const VoronoiDeviationOptions& o, VoronoiDeviation& out) {
  const auto n = static_cast<std::size_t>(cloud.size());
  check<InputError>(volumes.size() == n && cells.size() == n, "Voronoi deviation: ", volumes.size(), " volumes and ",
                    cells.size(), " cell measures for ", n, " particles");
  for (std::size_t i = 0; i < n; ++i) {
    check<InputError>(std::isfinite(volumes[i]) && volumes[i] >= 0, "Voronoi deviation: particle ", i, " has volume ",
                      volumes[i], " (must be finite and >= 0)");
    check<InputError>(std::isfinite(cells[i]) && cells[i] >= 0, "Voronoi deviation: particle ", i,
                      " has cell measure ", cells[i]);
    out.volume_sum += volumes[i];
    out.cell_sum += cells[i];
  }
  check<InputError>(out.cell_sum > 0, "Voronoi deviation: the cells have zero total measure");
  const Real mismatch = (out.volume_sum - out.cell_sum) / out.cell_sum;
  check<InputError>(std::abs(mismatch) <= 1e-9 || o.normalise_volumes, "the volumes sum to ", out.volume_sum,
                    " but the Voronoi cells to ", out.cell_sum, " (relative difference ", mismatch,
                    "): LP (63) is infeasible unless they agree ([IM] S9); pass --normalise-volumes to scale the volumes");
  out.volumes_normalised = o.normalise_volumes && mismatch != 0;
  const Real mean_cell = out.cell_sum / static_cast<Real>(n);
  Problem p;
  p.cells.resize(n);
  p.volumes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.cells[i] = cells[i] / mean_cell;
    p.volumes[i] = volumes[i] * (out.cell_sum / out.volume_sum) / mean_cell;
    check<InputError>(p.cells[i] > 0 || p.volumes[i] == 0, "particle ", i, " has an empty Voronoi cell (it lies outside "
                      "the domain) but volume ", volumes[i], ": d_N is infinite; exclude it or give it volume 0");
  }
  p.length_scale = cloud.spacing > 0 ? cloud.spacing : std::pow(mean_cell, 1.0 / cloud.dim);
  return p;
}

// Blocks are independent once the crossing flows are fixed: each writes only its own pairs'
// transport, so they run in parallel (one Clp model per block) and the result does not
// depend on the thread count. The first failure is rethrown after the loop.
void solve_blocks(const Problem& p, const std::vector<std::vector<Index>>& members, const std::vector<Index>& block_of,
                  Index nblocks, Transport& t, double max_seconds, VoronoiDeviation& out) {
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1)
  for (Index b = 0; b < nblocks; ++b) {
    try {
      const LpSize size = solve_block(p, members[static_cast<std::size_t>(b)], block_of, b, t, max_seconds);
#pragma omp critical(vrsph_voronoi_deviation)
      {
        out.variables = std::max(out.variables, size.variables);
        out.constraints = std::max(out.constraints, size.constraints);
      }
    } catch (...) {
#pragma omp critical(vrsph_voronoi_deviation)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

// d_N from the transport itself, after checking that it is one.
void deviation_from_transport(const Problem& p, const Transport& t, std::size_t n, VoronoiDeviation& out) {
  std::vector<Real> supply(t.self.begin(), t.self.end()), demand(t.self.begin(), t.self.end()), dev(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto nbr = p.pairs.of(static_cast<Index>(i));
    const auto dist = p.pairs.distances_of(static_cast<Index>(i));
    for (std::size_t s = 0; s < nbr.size(); ++s) {
      const auto j = static_cast<std::size_t>(nbr[s]);
      const Real a = t.pair[static_cast<std::size_t>(p.pairs.offsets[i]) + s];
      supply[i] += a;
      demand[j] += a;
      dev[i] += a * p.deviation_coefficient(i, dist[s]);
      dev[j] += a * p.deviation_coefficient(j, dist[s]);
    }
  }
  Real worst_balance = 0;
  for (std::size_t i = 0; i < n; ++i)
    worst_balance = std::max({worst_balance, std::abs(supply[i] - p.cells[i]), std::abs(demand[i] - p.volumes[i])});
  check<NumericalError>(worst_balance <= 1e-5, "Voronoi deviation: the LP's transport misses a cell or volume by ",
                        worst_balance, " (relative to the mean cell); the result would not be d_N");
  for (std::size_t i = 0; i < n; ++i)
    if (out.worst < 0 || dev[i] > out.value) out.value = dev[i], out.worst = static_cast<Index>(i);
  out.value *= p.length_scale;
}
}  // namespace

VoronoiDeviation voronoi_deviation(const PointCloud& cloud, std::span<const Real> volumes, std::span<const Real> cells,
                                   const VoronoiDeviationOptions& o) {
  validate(cloud);
  const Stopwatch clock;
  const auto n = static_cast<std::size_t>(cloud.size());
  VoronoiDeviation out;
  Problem p = scaled_problem(cloud, volumes, cells, o, out);
  const Real dx = p.length_scale;
  Vec3 lo = cloud.positions[0], hi = lo;
  for (const auto& x : cloud.positions) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Real diameter = (hi - lo).norm();
  check<InputError>(o.radius >= 0 && std::isfinite(o.radius), "Voronoi deviation: pair radius ", o.radius,
                    " (must be finite and >= 0)");
  Real rho = o.radius > 0 ? o.radius : 2 * dx;
  Index block_target = std::max<Index>(o.block_particles, 16);
  Index nblocks = 1;
  std::vector<Index> block_of;
  Transport t;
  // Retries: blocks whose crossing flows do not fit give way to one LP over the whole set
  // (merging blocks step by step was measured slower: every step failed again at 2.4e4
  // particles); one LP that is infeasible gets a 1.5 times larger pair radius (a few
  // times, then the error stands).
  // Without Clp (VRSPH_WITH_CLP=OFF) auto takes the potential flow at every size.
  bool flow = o.method == DeviationMethod::Flow ||
              (o.method == DeviationMethod::Auto && (cloud.size() > o.flow_above || VRSPH_HAVE_CLP == 0));
  for (int widen = 0;;) {
    const bool blocks = !flow && cloud.size() > o.direct_limit && block_target < cloud.size();
    block_of = blocks ? spatial_blocks(cloud, block_target, nblocks) : std::vector<Index>(n, 0);
    if (!blocks) nblocks = 1;
    std::vector<std::vector<Index>> members(static_cast<std::size_t>(nblocks));
    for (std::size_t i = 0; i < n; ++i) members[static_cast<std::size_t>(block_of[i])].push_back(static_cast<Index>(i));
    SearchParams sp;
    sp.radius = std::min(rho, 1.0001 * diameter) * (1 + 1e-12);
    sp.min_neighbours = 0;
    p.pairs = find_neighbours(cloud, sp);
    t.self.assign(n, 0);
    t.pair.assign(static_cast<std::size_t>(p.pairs.total()), 0);
    if (flow) {
      if (potential_flow(p, t)) break;
      // Auto falls back on the LP (e.g. lattices with particles on the faces, whose halved
      // face cells cannot pass on the interior's surplus along a potential).
      check<NumericalError>(o.method != DeviationMethod::Flow, "Voronoi deviation: the potential flow asks a cell to "
                            "pass on more than itself (the volumes are far from the cells); use --dn-method lp");
      flow = false;
      continue;
    }
    try {
      if (nblocks > 1) crossing_flows(p, block_of, nblocks, t);
      solve_blocks(p, members, block_of, nblocks, t, o.max_seconds, out);
      break;
    } catch (const NumericalError&) {
      if (nblocks > 1) {  // the crossing flows do not fit: one LP over the whole set, if affordable
        if (cloud.size() > o.fallback_limit) throw;
        block_target = cloud.size();
        out.block_fallback = true;
        continue;
      }
      if (rho >= diameter || ++widen > 4) throw;
      rho *= 1.5;
    }
  }
  out.radius = rho;
  out.blocks = nblocks;
  out.is_upper_bound = flow || nblocks > 1 || rho < diameter;
  out.method = flow ? "potential-flow" : nblocks > 1 ? "lp-blocks" : rho < diameter ? "lp-restricted" : "lp";
  deviation_from_transport(p, t, n, out);
  out.seconds = clock.seconds();
  return out;
}

}  // namespace vrsph
