#!/usr/bin/env bash
# Configure and build everything (Release, which is what the guarantees are tested in).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
launcher=()
# ccache, where installed, makes rebuilds in several work trees cheap; CI builds without it.
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$BUILD_DIR" -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)"
