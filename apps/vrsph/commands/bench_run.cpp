// SPDX-License-Identifier: BSD-3-Clause
#include "bench_run.hpp"

#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/methods/registry.hpp>
#include "../cli_common.hpp"

namespace vrsph::cli {

BvpStudyParams example5_bench_params(const std::string& command, int dim, const std::string& cloud, double h_factor,
                                     const std::string& method, const std::vector<std::string>& method_opts) {
  BvpStudyParams p;
  p.dim = dim;
  p.cloud = parse_cloud_family(cloud);
  check<ConfigError>(p.cloud == CloudFamily::Uniform || p.cloud == CloudFamily::Perturbed, "--cloud must be uniform "
                     "or perturbed for ", command, " (the peer's node sets)");
  p.h_factor = h_factor;
  p.measure_memory = true;
  p.check_m_matrix = false;
  p.method_options = parse_method_options(method_opts, {method});
  (void)builtin_methods().create(method, options_for(p.method_options, method));
  return p;
}

void warm_up_run(const BvpStudyParams& p, const std::string& method, std::uint64_t seed) {
  try {
    (void)run_bvp(p, method, 8, seed, false, nullptr, nullptr);
  } catch (const Interrupted&) {
    throw;
  } catch (const Error&) {
  }
}

void write_bench_cloud(const BvpStudyParams& p, int n, std::uint64_t seed, const std::string& path) {
  CloudSpec spec;
  spec.family = p.cloud;
  spec.box = Domain::unit_box(p.dim);
  spec.n = n;
  spec.delta = p.delta;
  spec.seed = seed;
  write_csv(path, make_study_cloud(spec).cloud);
}

}  // namespace vrsph::cli
