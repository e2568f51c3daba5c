#!/usr/bin/env bash
# Runs the libFuzzer harnesses of the readers (tests/fuzz/*_fuzz.cpp) on their seed corpora.
#
#   bash scripts/fuzz.sh <reader|all> [seconds per reader, default 60] [build dir, default build-asan]
#
# Readers: model_file expression csv mat set_json set_text. The harnesses come from the `asan`
# preset (cmake --preset asan && cmake --build --preset asan; scripts/sanitize.sh does both).
# New inputs go to <build>/fuzz/corpus/<reader>/ (the committed seeds in tests/fuzz/corpus/ are
# only read); a crash, sanitizer report, leak, timeout (> 10 s for one input) or allocation over
# 2 GB leaves its input in <build>/fuzz/artifacts/<reader>/ and makes the script fail. A long run,
# e.g. the 10 minutes per reader in docs/reliability.md:  bash scripts/fuzz.sh all 600
set -euo pipefail
cd "$(dirname "$0")/.."
reader=${1:?usage: scripts/fuzz.sh <reader|all> [seconds] [build dir]}
seconds=${2:-60}
build=${3:-build-asan}
readers=(model_file expression csv mat set_json set_text)
if [ "$reader" != all ]; then readers=("$reader"); fi

symbolizer=$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:allocator_may_return_null=0${symbolizer:+:external_symbolizer_path=$symbolizer}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

status=0
for r in "${readers[@]}"; do
  exe="$build/tests/fuzz/fuzz_$r"
  if [ ! -x "$exe" ]; then
    echo "fuzz.sh: $exe is missing (cmake --preset asan && cmake --build --preset asan)" >&2
    exit 1
  fi
  work="$build/fuzz/corpus/$r"
  artifacts="$build/fuzz/artifacts/$r/"
  log="$build/fuzz/$r.log"
  mkdir -p "$work" "$artifacts"
  options=(-max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10
           -print_final_stats=1 -artifact_prefix="$artifacts")
  if [ -f "tests/fuzz/$r.dict" ]; then options+=(-dict="tests/fuzz/$r.dict"); fi
  if [ "$r" = mat ]; then options+=(-max_len=16384); fi  # room for compressed variables
  if "$exe" "${options[@]}" "$work" "tests/fuzz/corpus/$r" >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    echo "fuzz_$r: ${execs:-?} inputs in ${seconds} s, corpus $(ls "$work" | wc -l) files (+ $(ls "tests/fuzz/corpus/$r" | wc -l) seeds), 0 crashes"
  else
    tail -n 80 "$log"
    echo "fuzz_$r: FAILED (log: $log, input: $(ls -t "$artifacts" | head -1))"
    status=1
  fi
done
exit $status
