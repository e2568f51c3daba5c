#!/usr/bin/env bash
# The sanitizer part of CI (scripts/test.sh runs it when SETS_SANITIZERS=1; .ci/run sets it):
#  1. preset `asan` (Clang, AddressSanitizer + UndefinedBehaviorSanitizer, -O1, -frounding-math):
#     library, apps, test suite and the libFuzzer harnesses; the whole test suite under it;
#  2. every fuzz harness for SETS_FUZZ_SECONDS (default 45) seconds on its seed corpus;
#  3. preset `tsan` (ThreadSanitizer): the tests that run PUIs from several threads at once
#     (skipped with SETS_TSAN=0: CI's subset, see docs/reliability.md "Sanitizers").
# Each step fails the script on the first report. Prerequisites: scripts/install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
symbolizer=$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)
export ASAN_SYMBOLIZER_PATH=$symbolizer TSAN_SYMBOLIZER_PATH=$symbolizer UBSAN_SYMBOLIZER_PATH=$symbolizer
jobs=$(nproc)
step() { echo "== sanitize.sh: $* ($(date +%T))"; }

step "asan: configure and build"
cmake --preset asan "${launcher[@]}" >/dev/null
cmake --build --preset asan -j "$jobs"
step "asan: test suite"
ctest --preset asan -j "$jobs"
step "asan: fuzz harnesses, ${SETS_FUZZ_SECONDS:-45} s each"
bash scripts/fuzz.sh all "${SETS_FUZZ_SECONDS:-45}" build-asan
if [ "${SETS_TSAN:-1}" = 1 ]; then
  step "tsan: configure and build"
  cmake --preset tsan "${launcher[@]}" >/dev/null
  cmake --build --preset tsan -j "$jobs"
  step "tsan: concurrent PUIs"
  ctest --preset tsan -j "$jobs"
else
  step "tsan: skipped (SETS_TSAN=0; run: cmake --preset tsan && cmake --build --preset tsan && ctest --preset tsan)"
fi
step "done"
