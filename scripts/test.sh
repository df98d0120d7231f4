#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs dependencies, builds, and runs the tests (.ci/run calls this). Two tiers:
#
#   bash scripts/test.sh          the default (CI; about 11 minutes on 2 cores, packages installed):
#     1. the core configuration (no optional part but muParser: preset core-asan, clang) under
#        AddressSanitizer + UndefinedBehaviorSanitizer: the unit and error tests and cli_parts,
#        which checks that every feature of a missing part says so;
#     2. the Release build with every part: every test except the long tier.
#   bash scripts/test.sh --full   adds the long tier (VRSPH_FULL_TESTS: the long reproductions and
#     convergence cases, units_and_limits, the CLI argument fuzz sample, mpi_cli, the STL example,
#     the wheel in a virtual environment) and the sanitizer build of every part (preset
#     asan-ubsan: unit, errors, cli, fuzz-replay); about 45 minutes.
#
# CTest's summary line of the last stage closes the output.
set -euo pipefail
cd "$(dirname "$0")/.."
full=OFF
for arg in "$@"; do
  case "$arg" in
    --full) full=ON ;;
    *) echo "usage: scripts/test.sh [--full]" >&2; exit 2 ;;
  esac
done
bash scripts/setup.sh
jobs=$(nproc)
stage() { printf '\n== %s (%s)\n' "$1" "$(date +%T)"; }

stage "core configuration under ASan + UBSan"
cmake --preset core-asan >/dev/null
cmake --build --preset core-asan -j "$jobs" --target test_unit test_errors vrsph_cli
ctest --preset core-asan -j "$jobs"

if [[ $full == ON ]]; then
  stage "every part under ASan + UBSan"
  cmake --preset asan-ubsan >/dev/null
  cmake --build --preset asan-ubsan -j "$jobs" --target test_unit test_errors vrsph_cli fuzz_replay
  ctest --preset asan-ubsan -j "$jobs"
fi

stage "Release, every part$([[ $full == ON ]] && echo ', long tier included')"
# The benchmarks are built by scripts/run.sh and bench presets, not by the tests.
# GoogleTest cases in two shards per executable (VRSPH_TEST_SHARDS): a process of this build
# starts in 0.13 s, a third of the test time when every case was its own process.
cmake --preset release -DVRSPH_FULL_TESTS=$full -DVRSPH_BUILD_BENCH=$full -DVRSPH_TEST_SHARDS=2 >/dev/null
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"
