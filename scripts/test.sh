#!/usr/bin/env bash
# README command 2: install dependencies, build, and run the whole test suite.
# With SETS_CHECK_INSTALL=1 (CI) it also installs the library and builds examples/consumer
# against it before running the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
if [ "${SETS_CHECK_INSTALL:-0}" = 1 ]; then bash scripts/check-install.sh; fi
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j "$(nproc)"
