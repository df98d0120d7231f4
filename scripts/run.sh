#!/usr/bin/env bash
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
# Default: [QW] Example 5 / Table 2 (seed 000): div((1+x^2+y^2) grad u) = f on [0,1]^2,
# u = sin(pi x) sin(pi y), randomly perturbed particles, h = 3 dx, traditional SPH next to
# VRSPH, n = 20..160. (Mean over five seeds, as in the tests: add --seeds 1,2,3,4,5.)
echo "## [QW] Table 2: perturbed particles, SPH vs VRSPH (seed 1)"
"$vrsph" study --problem qw-ex5 --method sph,vrsph --cloud perturbed --n 20,40,80,160 --seed 1
