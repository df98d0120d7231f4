#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job: install dependencies, build Release, and run vrsph on its built-in
# default problem. Extra arguments replace the default job: scripts/run.sh methods
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" >/dev/null
vrsph=build/release/apps/vrsph/vrsph
if (($#)); then
  exec "$vrsph" "$@"
fi
# Default: [QW] Example 5 / Table 2: div((1+x^2+y^2) grad u) = f on [0,1]^2,
# u = sin(pi x) sin(pi y), randomly perturbed particles, h = 3 dx, n = 20..160: traditional
# SPH, [QW]'s VRSPH as published (profile=qw), vrsph's default rows (compact rows with
# the M-matrix kept) and its rows of degree 6 side by side. (Mean over five seeds, as in the tests: add --seeds 1,2,3,4,5.)
run_table() {
  "$vrsph" study --problem qw-ex5 --cloud perturbed --n 20,40,80,160 --seed 1 \
    --columns method,n,N,error_inf,order_inf,error_l2,mmatrix,infeasible,solver_iterations,seconds_total "$@"
}
echo "## [QW] Table 2: perturbed particles (seed 1)"
echo
echo "### SPH"
run_table --method sph
echo
echo "### VRSPH as published in [QW] (--method-opt vrsph:profile=qw)"
run_table --method vrsph --method-opt vrsph:profile=qw
echo
echo "### vrsph default (rhs=compact, flux=balance: third order, -L an M-matrix)"
run_table --method vrsph
echo
echo "### vrsph with compact rows of degree 6 (--method-opt vrsph:compact_degree=6: O(h^6) inside; at n = 160 two rows by a wall set the max error)"
run_table --method vrsph --method-opt vrsph:compact_degree=6
