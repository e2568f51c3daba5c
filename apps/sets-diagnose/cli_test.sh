#!/usr/bin/env bash
# Command-line checks of sets-diagnose: the exit-code and output contract of docs/contributing.md
# (issue 12, point 4): usage errors exit 1 (not CLI11's codes), numbers whole, output paths checked
# before the work, the report folder written as a whole, nothing of ours left after a kill.
# Usage: cli_test.sh /path/to/sets-diagnose
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

# A first-order decay with a free rate, and a recording of it (awk: no Python needed).
cat >"$dir/model.json" <<'JSON'
{"name": "decay", "sample_time": 0.1, "inputs": {"u": "u"},
 "parameters": {"a": {"value": 1.0, "min": 0.1, "max": 10}}, "states": {"x": 0.0},
 "derivatives": {"x": "-a*x + u"}, "outputs": {"x": "y"}}
JSON
awk 'BEGIN { print "u,y"; x = 0; for (k = 0; k < 200; ++k) { u = (int(k / 25) % 2) ? 1 : -1;
  printf "%.17g,%.17g\n", u, x; for (s = 0; s < 100; ++s) x += 0.001 * (-2 * x + u) } }' >"$dir/good.csv"

check "usage: --threads 0 exits 1, not CLI11's 105" 1 "--threads" -- "$app" --example --threads 0
check "usage: an unknown flag exits 1, not CLI11's 109" 1 "--bogus" -- "$app" --bogus
check "usage: --help" 0 "--report" -- "$app" --help
check "--threads with trailing text" 1 "--threads: .*12:30" -- "$app" --example --threads 12:30
check "--threads not whole" 1 "--threads: .*2.5" -- "$app" --example --threads 2.5
check "missing --data" 1 "give --model and --data" -- "$app" --model "$dir/model.json"
sed 's/"value": 1.0/"value": 1e400/' "$dir/model.json" >"$dir/huge.json"
check "1e400 in the model file: our error with file, line and column" 1 "huge.json.*line 2, column" -- \
  "$app" --model "$dir/huge.json" --data "$dir/good.csv" --quiet
check_silent_stdout "1e400: no JSON library exception" "sets-diagnose: error: .*huge.json"
sed '101s/^[^,]*,/0.5abc,/' "$dir/good.csv" >"$dir/abc.csv"
check "data: a number with trailing text" 1 "abc.csv: line 101, column 1 \(\"u\"\): not a number: \"0.5abc\"" -- \
  "$app" --model "$dir/model.json" --data "$dir/abc.csv" --quiet
sed '101s/^[^,]*,/12:30,/' "$dir/good.csv" >"$dir/time.csv"
check "data: a time of day" 1 "time.csv: line 101, column 1 \(\"u\"\): not a number: \"12:30\"" -- \
  "$app" --model "$dir/model.json" --data "$dir/time.csv" --quiet
{ head -100 "$dir/good.csv"; printf '\x1b[2J\x07\xff,0.1\n'; } >"$dir/garbage.csv"
check "data: binary garbage" 1 "garbage.csv: line 101, column 1" -- "$app" --model "$dir/model.json" --data "$dir/garbage.csv" --quiet
check_printable "binary garbage is escaped in the message"

# A rate written with the wrong sign (x grows as e^(40 t): no longer finite within the 20 s record):
# the file's values have no fit, the other starts are calibrated; with the rate fixed there is no
# other start, and the numerical failure exits 3 naming the time.
sed 's/"a": {"value": 1.0, "min": 0.1, "max": 10}/"a": -40.0/' "$dir/model.json" >"$dir/unstable.json"
check "file values that blow up: calibrated from the other starts" 0 "file values, estimation +y not available" -- \
  "$app" --model "$dir/unstable.json" --data "$dir/good.csv" --quiet
sed 's/"a": {"value": 1.0, "min": 0.1, "max": 10}/"a": {"value": -40.0, "fixed": true}/' "$dir/model.json" >"$dir/fixed.json"
check "file values that blow up, nothing free: numerical failure" 3 "from any start.*blew up at t = " -- \
  "$app" --model "$dir/fixed.json" --data "$dir/good.csv" --quiet

# Output paths are checked before the work: nothing is computed, nothing written.
mkdir "$dir/k"
check "bad --json with a good --report" 1 "--json .*does not exist" -- \
  "$app" --example --quiet --json "$dir/k/no/d.json" --report "$dir/k/report"
check_silent_stdout "bad --json stops before the diagnosis" "sets-diagnose: error: "
check_listing "bad --json: no report written" "$dir/k"
check "--report in a missing folder" 1 "--report .*does not exist" -- "$app" --example --quiet --report "$dir/k/no/report"
check_listing "bad --report: nothing written" "$dir/k"
mkdir "$dir/k/mine" && touch "$dir/k/mine/thesis.tex"
check "--report into a folder with other files" 1 "holds 'thesis.tex'" -- "$app" --example --quiet --report "$dir/k/mine"
check_listing "the other files are untouched" "$dir/k/mine" thesis.tex
rm -r "$dir/k/mine"

# A report is written as a whole, and replaces an older one as a whole.
check "report" 0 "Augmented model written to" -- "$app" --example --quiet --report "$dir/k/report" --json "$dir/k/d.json"
check_listing "report folder" "$dir/k/report" augmented_model.json index.html report.txt signals_estimation.png \
  signals_validation.png signature.png
check_listing "beside the report: only the JSON" "$dir/k" d.json report
# The folder written with a trailing separator (README's command: --report report/) is the same folder.
check "report/ with a trailing separator" 0 "Augmented model written to" -- "$app" --example --quiet --report "$dir/k/report/"
check_listing "report/: the same folder, replaced" "$dir/k" d.json report

# Killed while writing the report: SIGTERM leaves neither a partial report nor a temporary; after
# SIGKILL, the next run removes the stale temporary.
rm -r "$dir/k"/*
if signal_during TERM "$dir/k/.report.sets-tmp.*" -- "$app" --example --quiet --report "$dir/k/report"; then
  [[ $signal_status -eq 143 ]] || { echo "FAIL SIGTERM: status $signal_status"; fail=1; }
  check_listing "SIGTERM while writing the report leaves nothing" "$dir/k"
else
  echo "FAIL SIGTERM: the report's temporary never appeared (status $signal_status)"; fail=1
fi
if signal_during KILL "$dir/k/.report.sets-tmp.*" -- "$app" --example --quiet --report "$dir/k/report"; then
  sleep 1  # gnuplot, orphaned, finishes
  compgen -G "$dir/k/.report.sets-tmp.*" >/dev/null || { echo "FAIL SIGKILL left no temporary (test not meaningful)"; fail=1; }
  check "next run after SIGKILL" 0 "Augmented model written to" -- "$app" --example --quiet --report "$dir/k/report"
  check_listing "the stale temporary is removed by the next run" "$dir/k" report
else
  echo "FAIL SIGKILL: the report's temporary never appeared"; fail=1
fi
exit $fail
