#!/usr/bin/env bash
# Command-line checks of sets-ss-uncertainty: results on a small Monte Carlo study and on a data
# file, and the exit-code and output contract of docs/contributing.md (issue 12, point 4).
# Usage: cli_test.sh /path/to/sets-ss-uncertainty
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

# A 2-input 2-output second-order system with small output noise (awk: no Python needed).
awk 'BEGIN { srand(7); T = 600; print "u1,u2,y1,y2"; x1 = 0; x2 = 0;
  for (t = 1; t <= T; ++t) { a = (rand() < 0.5) ? -1 : 1; b = (rand() < 0.5) ? -1 : 1;
    printf "%.17g,%.17g,%.17g,%.17g\n", a, b, x1 + 0.01 * (2 * rand() - 1), x2 + 0.01 * (2 * rand() - 1);
    n1 = 0.7 * x1 + 0.2 * x2 + a; n2 = -0.1 * x1 + 0.5 * x2 + 0.5 * b; x1 = n1; x2 = n2; } }' >"$dir/good.csv"
data=(--data "$dir/good.csv" --inputs u1,u2 --outputs 3,4 --order 2 --past 8)

check "Monte Carlo" 0 "Table I" -- "$app" --runs 4 --threads 2 --json "$dir/mc.json"
grep -q '"estimate_fps_full"' "$dir/mc.json" || { echo "FAIL Monte Carlo JSON"; fail=1; }
grep -q '"guaranteed_fps_full"' "$dir/mc.json" || { echo "FAIL Monte Carlo JSON: no guaranteed set"; fail=1; }
check "Monte Carlo, bounded noise" 0 "runs that met the assumption: 4 of 4" -- "$app" --runs 4 --noise uniform
check "bad --noise" 1 "--noise" -- "$app" --runs 1 --noise laplace
check "data, columns by name and number" 0 "FPS PUI" -- "$app" "${data[@]}" --json "$dir/d.json"
grep -q '"pui_guaranteed"' "$dir/d.json" || { echo "FAIL data JSON"; fail=1; }
check "data without --order" 1 "--order" -- "$app" --data "$dir/good.csv" --inputs 1,2 --outputs 3,4
check "unknown column" 1 "y9" -- "$app" --data "$dir/good.csv" --inputs 1,2 --outputs y1,y9 --order 2
check "bad --rows" 1 "--rows: '1:x'" -- "$app" --runs 1 --rows 1:0,1:x

# ---- The exit-code and output contract (issue 12, point 4).
sed '101s/^[^,]*,/0.5abc,/' "$dir/good.csv" >"$dir/abc.csv"
check "data: a number with trailing text" 1 "abc.csv: line 101, column 1 \(\"u1\"\): not a number: \"0.5abc\"" -- \
  "$app" --data "$dir/abc.csv" --inputs u1,u2 --outputs 3,4 --order 2 --past 8
sed '101s/^[^,]*,/12:30,/' "$dir/good.csv" >"$dir/time.csv"
check "data: a time of day" 1 "time.csv: line 101, column 1 \(\"u1\"\): not a number: \"12:30\"" -- \
  "$app" --data "$dir/time.csv" --inputs u1,u2 --outputs 3,4 --order 2 --past 8
{ head -100 "$dir/good.csv"; printf '\x1b[2J\x07\xff,1,0.1,0.2\n'; } >"$dir/garbage.csv"
check "data: binary garbage" 1 "garbage.csv: line 101, column 1" -- \
  "$app" --data "$dir/garbage.csv" --inputs u1,u2 --outputs 3,4 --order 2 --past 8
check_printable "binary garbage is escaped in the message"
tr ',' ';' <"$dir/good.csv" >"$dir/semicolons.csv"
check "data separated by semicolons" 0 "FPS PUI" -- "$app" --data "$dir/semicolons.csv" --inputs u1,u2 --outputs y1,y2 --order 2 --past 8
check "usage: --threads 0 exits 1" 1 "--threads" -- "$app" --threads 0
check "usage: unknown flag exits 1" 1 "--bogus" -- "$app" --bogus
check "--runs with trailing text" 1 "--runs: .*12:30" -- "$app" --runs 12:30
check "--snr-db with trailing text" 1 "--snr-db: '20dB' is not a number" -- "$app" --runs 1 --snr-db 20dB
check "NaN --snr-db" 1 "--snr-db: 'nan' is not a finite number" -- "$app" --runs 1 --snr-db nan
check "infinite --level-factor" 1 "--level-factor: 'inf' is not a finite number" -- "$app" --runs 1 --level-factor inf
mkdir "$dir/k"
check "--json into a missing folder" 1 "--json .*does not exist" -- "$app" --runs 2 --json "$dir/k/no/out.json"
check_silent_stdout "--json checked before the work" "sets-ss-uncertainty: error: "
check_listing "nothing written beside a bad --json" "$dir/k"
"$app" --runs 100000 --threads 2 --json "$dir/k/t.json" >/dev/null 2>&1 &
pid=$!
sleep 0.5
kill -TERM $pid
wait $pid 2>/dev/null
[[ $? -eq 143 ]] || { echo "FAIL SIGTERM did not end the run"; fail=1; }
check_listing "SIGTERM during a run leaves nothing" "$dir/k"
exit $fail
