#!/usr/bin/env bash
# Configure and build everything (Release, which is what the guarantees are tested in).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)"
