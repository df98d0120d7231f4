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
# Default: [QW] Examples 1 and 2 (seed 000) for traditional SPH, gradient and
# Laplacian on uniform and randomly perturbed particles, h = 3 dx, N^{1/d} = 2^3..2^7.
for cloud in uniform perturbed; do
  for op in gradient laplacian; do
    echo "## SPH ${op}, ${cloud} particles ([QW] Example $([[ $cloud == uniform ]] && echo 1 || echo 2), h = 3 dx, with ghosts)"
    "$vrsph" operator --problem qw-trunc --method sph --operator "$op" --cloud "$cloud" --n 8,16,32,64,128 --seed 1 --h-factor 3
    echo
  done
done
