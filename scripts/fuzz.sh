#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds the libFuzzer harnesses (clang, ASan + UBSan; preset `fuzz`) and fuzzes each for
# SECONDS (default 600), one after the other. New inputs that add coverage are merged
# (minimised) into fuzz/corpus/<harness>, which CTest replays (label fuzz-replay).
# A crash, leak, sanitizer report or hang (> 10 s per input) stops with the reproducer
# in build/fuzz/findings/. Statistics: build/fuzz/findings/<harness>.log (last lines).
#   bash scripts/fuzz.sh [SECONDS] [HARNESS ...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
harnesses=("$@")
((${#harnesses[@]})) || harnesses=(csv_reader expression method_options vtk_cloud geojson gmsh_cloud surface problem_file)
bash scripts/setup.sh
command -v clang++ >/dev/null || apt-get install -y -qq clang libclang-rt-14-dev >/dev/null
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null
mkdir -p build/fuzz/findings
for h in "${harnesses[@]}"; do
  work=build/fuzz/work/$h
  rm -rf "$work" && mkdir -p "$work"
  echo "fuzz: $h for $seconds s" >&2
  build/fuzz/fuzz/fuzz_$h -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix=build/fuzz/findings/"$h"- -print_final_stats=1 "$work" fuzz/corpus/"$h" \
    >build/fuzz/findings/"$h".log 2>&1
  build/fuzz/fuzz/fuzz_$h -merge=1 fuzz/corpus/"$h" "$work" >>build/fuzz/findings/"$h".log 2>&1
  grep -E "^stat::|cov:" build/fuzz/findings/"$h".log | tail -6 >&2
done
