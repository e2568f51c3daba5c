#!/usr/bin/env bash
# Installs every build, test and plot dependency of `sets` from Debian packages (clang-14,
# libFuzzer and llvm-symbolizer for the sanitizer builds and fuzz harnesses of scripts/sanitize.sh).
# Used by the README's two commands and by .ci/run; safe to run again.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake ninja-build pkg-config python3 \
  libeigen3-dev libboost-dev libcgal-dev libgmp-dev libmpfr-dev \
  libglpk-dev \
  libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev \
  libcli11-dev nlohmann-json3-dev libmuparser-dev libmatio-dev zlib1g-dev \
  gnuplot-nox \
  clang-14 libfuzzer-14-dev libclang-rt-14-dev llvm-14 \
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-matplotlib python3-pytest \
  python3-dask python3-distributed chromium >/dev/null
