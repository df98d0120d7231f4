#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds vrsph with its default options where only the core's packages are visible, and runs
# its tests: every optional part's headers, CMake configs and pkg-config files are hidden in a
# private mount namespace (unshare -m, root), as if only Eigen, nanoflann, GoogleTest, CLI11 and
# muParser were installed. The configuration must turn the parts off by itself.
#
#   bash scripts/check_minimal_core.sh [BUILD_DIR]     (default /tmp/vrsph-minimal-core)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-/tmp/vrsph-minimal-core}
if [[ ${VRSPH_IN_NAMESPACE:-} != 1 ]]; then
  [[ $(id -u) == 0 ]] || { echo "check_minimal_core.sh: needs root (unshare -m)" >&2; exit 2; }
  exec env VRSPH_IN_NAMESPACE=1 unshare -m bash "$0" "$build"
fi
empty=$(mktemp -d)
lib=/usr/lib/x86_64-linux-gnu
for d in /usr/include/nlohmann /usr/share/cmake/nlohmann_json /usr/include/toml++ $lib/cmake/tomlplusplus \
         /usr/include/CGAL $lib/cmake/CGAL /usr/include/coin /usr/include/suitesparse $lib/cmake/pugixml \
         /usr/include/petsc /usr/lib/petscdir; do
  if [[ -e $d ]]; then mount --bind "$empty" "$d"; fi
done
for f in /usr/include/pugixml.hpp /usr/include/umfpack.h $lib/pkgconfig/PETSc.pc $lib/pkgconfig/petsc.pc \
         $lib/pkgconfig/clp.pc $lib/pkgconfig/osi-clp.pc $lib/pkgconfig/tomlplusplus.pc; do
  if [[ -e $f ]]; then mount --bind /dev/null "$f"; fi
done
cmake -S "$src" -B "$build" -G Ninja -DVRSPH_BUILD_PYTHON=OFF -DVRSPH_BUILD_BENCH=OFF | grep "optional parts built"
cmake --build "$build" -j "$(nproc)"
cd "$build" && ctest -j "$(nproc)"
