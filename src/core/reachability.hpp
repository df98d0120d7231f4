// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: which nodes can reach a seed node along directed edges i -> j. The edges are
// stored reversed in CSR form (for each j, every i with an edge i -> j), built in two
// passes over the caller's edges (count, then fill): one allocation for any number of
// nodes, where a vector per node cost ~10^6 small allocations for a large system.
// Shared by the M-matrix test (reach a strictly dominant row) and the assembly's
// singularity check (reach a row coupled to a Dirichlet particle).
#include <span>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph::detail {

struct ReverseGraph {
  std::vector<std::size_t> offset;  ///< size n + 1
  std::vector<Index> source;        ///< sources of the edges into j: source[offset[j] .. offset[j+1])
};

/// for_each_edge(emit) must call emit(i, j) for every edge i -> j, the same edges each
/// time it is called (it is called twice).
template <class ForEachEdge>
ReverseGraph reverse_graph(Index n, ForEachEdge&& for_each_edge) {
  ReverseGraph g;
  g.offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for_each_edge([&](Index, Index j) { ++g.offset[static_cast<std::size_t>(j) + 1]; });
  for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) g.offset[j + 1] += g.offset[j];
  g.source.resize(g.offset.back());
  std::vector<std::size_t> fill(g.offset.begin(), g.offset.end() - 1);
  for_each_edge([&](Index i, Index j) { g.source[fill[static_cast<std::size_t>(j)]++] = i; });
  return g;
}

inline std::vector<char> reaching(const ReverseGraph& g, std::vector<char> seeds) {
  std::vector<Index> queue;
  queue.reserve(seeds.size());
  for (std::size_t i = 0; i < seeds.size(); ++i)
    if (seeds[i]) queue.push_back(static_cast<Index>(i));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto j = static_cast<std::size_t>(queue[head]);
    for (std::size_t k = g.offset[j]; k < g.offset[j + 1]; ++k) {
      const Index i = g.source[k];
      if (!seeds[static_cast<std::size_t>(i)]) {
        seeds[static_cast<std::size_t>(i)] = 1;
        queue.push_back(i);
      }
    }
  }
  return seeds;
}

/// The nodes that reach a seed along the edges i -> j given in CSR form (j in
/// targets[offsets[i] .. offsets[i+1])): the closure of one process's graph.
inline std::vector<char> reaching(std::span<const Index> offsets, std::span<const Index> targets,
                                  std::vector<char> seeds) {
  const auto n = static_cast<Index>(offsets.size()) - 1;
  const auto reverse = reverse_graph(n, [&](auto&& emit) {
    for (Index i = 0; i < n; ++i)
      for (Index k = offsets[static_cast<std::size_t>(i)]; k < offsets[static_cast<std::size_t>(i) + 1]; ++k)
        emit(i, targets[static_cast<std::size_t>(k)]);
  });
  return reaching(reverse, std::move(seeds));
}

}  // namespace vrsph::detail
