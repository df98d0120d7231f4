#pragma once
// Internal: which nodes can reach a seed node along directed edges i -> j, given the
// reversed adjacency (reverse[j] lists every i with an edge i -> j). Breadth-first.
// Shared by the M-matrix test (reach a strictly dominant row) and the assembly's
// singularity check (reach a row coupled to a Dirichlet particle).
#include <deque>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph::detail {

inline std::vector<char> reaching(const std::vector<std::vector<Index>>& reverse, std::vector<char> seeds) {
  std::deque<Index> queue;
  for (std::size_t i = 0; i < seeds.size(); ++i)
    if (seeds[i]) queue.push_back(static_cast<Index>(i));
  while (!queue.empty()) {
    const Index j = queue.front();
    queue.pop_front();
    for (Index i : reverse[static_cast<std::size_t>(j)])
      if (!seeds[static_cast<std::size_t>(i)]) {
        seeds[static_cast<std::size_t>(i)] = 1;
        queue.push_back(i);
      }
  }
  return seeds;
}

}  // namespace vrsph::detail
