#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test: first the unit, error and CLI
# tests under AddressSanitizer + UndefinedBehaviorSanitizer, then the whole CTest
# suite on the Release build (its summary line closes the output).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)
cmake --preset asan-ubsan >/dev/null
# Only what the sanitizer stage runs (unit, errors, cli, fuzz-replay); convergence and published
# studies run in the Release build below.
cmake --build --preset asan-ubsan -j "$jobs" --target test_unit test_errors vrsph_cli fuzz_replay
ctest --preset asan-ubsan -j "$jobs"
cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"
