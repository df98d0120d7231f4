#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs the Debian packages vrsph needs, if any are missing (idempotent, quiet when
# nothing is to do). Run as root (or with sudo available).
set -euo pipefail
packages=(
  cmake ninja-build g++ clang libclang-rt-dev pkg-config
  libeigen3-dev libnanoflann-dev libcli11-dev libtomlplusplus-dev libmuparser-dev nlohmann-json3-dev libcgal-dev
  libsuitesparse-dev coinor-libclp-dev libpugixml-dev zlib1g-dev libgtest-dev libbenchmark-dev petsc-dev openmpi-bin
  python3 python3-numpy python3-matplotlib python3-dev pybind11-dev python3-scipy python3-pytest
  python3-pip python3-venv python3-setuptools python3-wheel dpkg-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
