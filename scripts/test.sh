#!/usr/bin/env bash
# README command 2: install dependencies, build, and run the whole test suite.
# With SETS_CHECK_INSTALL=1 (CI) it also installs the library and builds examples/consumer
# against it before running the tests; with SETS_SANITIZERS=1 (CI) it then runs the ASan/UBSan
# suite, a short run of every fuzz harness and the TSan test (scripts/sanitize.sh; CI sets
# SETS_FUZZ_SECONDS=30 SETS_TSAN=0, see docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
if [ "${SETS_CHECK_INSTALL:-0}" = 1 ]; then bash scripts/check-install.sh; fi
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j "$(nproc)"
if [ "${SETS_SANITIZERS:-0}" = 1 ]; then bash scripts/sanitize.sh; fi
