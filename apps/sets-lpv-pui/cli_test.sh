#!/usr/bin/env bash
# Command-line checks of sets-lpv-pui: exit codes and messages for good data, bad input and
# falsified data. Usage: cli_test.sh /path/to/sets-lpv-pui
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

# Section IV's system, 200 samples, |eta|, |eps| <= 1e-3 (awk: no Python needed).
awk 'BEGIN {
  srand(3); T = 200; d = 1e-3; print "t,u,y,r";
  w1 = 0; w2 = 0; u1 = 0; u2 = 0;
  for (t = 1; t <= T; ++t) {
    u = 2 * rand() - 1; l = 2 * rand() - 1;
    w = -(0.5 * l) * w1 - (-0.2 + 0.3 * l * l) * w2 + 0.1 * u1 + (1.0 * l + 0.2 * l * l) * u2;
    printf "%d,%.17g,%.17g,%.17g\n", t, u, w + d * (2 * rand() - 1), l + d * (2 * rand() - 1);
    w2 = w1; w1 = w; u2 = u1; u1 = u;
  }
}' >"$dir/good.csv"
data=(--data "$dir/good.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3)

check "good data" 0 "certified by a safe bound: yes" -- "$app" "${data[@]}"
check "good data, structure by flags" 0 "a2,2\[lambda\^2\]" -- \
  "$app" "${data[@]}" --a lambda --a 1,lambda^2 --b "" --b 1 --b lambda,lambda^2
echo '{"alpha": 1, "a": [["lambda"], ["1", "lambda^2"]], "b": [[], ["1"], ["lambda", "lambda^2"]]}' >"$dir/model.json"
check "good data, structure by JSON" 0 "b2,1\[lambda\]" -- "$app" "${data[@]}" --model "$dir/model.json" --json "$dir/out.json"
grep -q '"guaranteed": true' "$dir/out.json" || { echo "FAIL json output"; fail=1; }
echo '{"alpha": 1, "a": [["lambda"], ["1", "lambda^2"]],
 "b": [[], [1e400], ["lambda", "lambda^2"]]}' >"$dir/huge.json"
check "1e400 in the model JSON: our error with file, line and column" 1 "huge.json.*line 2, column" -- \
  "$app" "${data[@]}" --model "$dir/huge.json"
check_silent_stdout "1e400: no JSON library exception" "sets-lpv-pui: error: .*huge.json"

sed '51s/^\([0-9]*\),\([^,]*\),[^,]*,/\1,\2,nan,/' "$dir/good.csv" >"$dir/nan.csv"
check "NaN sample" 1 "nan.csv: data row 50 \(line 51\), column \"y\": NaN or infinite value" -- \
  "$app" --data "$dir/nan.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
check "negative bound" 1 "delta-eta.*>= 0" -- "$app" --data "$dir/good.csv" --u u --y y --r r --delta-eta -1 --delta-eps 1e-3
head -6 "$dir/good.csv" >"$dir/short.csv"
check "more parameters than samples" 1 "3 regressions .* for 6 parameters" -- \
  "$app" --data "$dir/short.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
awk -F, 'NR == 101 { $3 = $3 + 5 } { print }' OFS=, "$dir/good.csv" >"$dir/falsified.csv"
check "falsified data" 2 "sample 10[0-2] \(line 10[2-4]\)" -- \
  "$app" --data "$dir/falsified.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
check "unknown column" 1 "good.csv: no column \"x\" \(given by --u\)" -- "$app" --data "$dir/good.csv" --u x --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
check "bad basis" 1 "gamma" -- "$app" "${data[@]}" --a "gamma(lambda)" --b 1
check "bad table" 1 "" -- "$app" --table V
check "table I, one run, JSON" 0 "true theta in all PUIs: 1/1" -- "$app" --table I --runs 1 --threads 2 --json "$dir/t.json"
# Table II diagnostics (docs/reproduction/cerone.md): the unguaranteed variant must say so; the
# lagged-coefficient reading simulates and identifies the same model, so it must still cover theta.
check "diagnostic regressor boxes are labelled" 0 "DIAGNOSTIC regressor boxes \(not guaranteed\)" -- \
  "$app" --table II --runs 1 --regressor-noise scheduling
check "bad --regressor-noise" 1 "" -- "$app" --table II --runs 1 --regressor-noise sometimes
check "lagged coefficients cover theta" 0 "true theta in all PUIs: 3/3" -- "$app" --table II --runs 3 --coefficient-time lagged
grep -q '"coverage": 1.0' "$dir/t.json" || { echo "FAIL table json"; fail=1; }

# ---- The exit-code and output contract (issue 12, point 4).
sed '51s/^\([0-9]*\),[^,]*,/\1,0.5abc,/' "$dir/good.csv" >"$dir/abc.csv"
check "data: a number with trailing text" 1 "abc.csv: line 51, column 2 \(\"u\"\): not a number: \"0.5abc\"" -- \
  "$app" --data "$dir/abc.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
sed '51s/^\([0-9]*\),[^,]*,/\1,12:30,/' "$dir/good.csv" >"$dir/time.csv"
check "data: a time of day" 1 "time.csv: line 51, column 2 \(\"u\"\): not a number: \"12:30\"" -- \
  "$app" --data "$dir/time.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
{ head -50 "$dir/good.csv"; printf '50,\x1b[2J\x07\xff,0.1,0.2\n'; } >"$dir/garbage.csv"
check "data: binary garbage" 1 "garbage.csv: line 51, column 2" -- \
  "$app" --data "$dir/garbage.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps 1e-3
check_printable "binary garbage is escaped in the message"
check "usage: --threads 0 exits 1" 1 "--threads" -- "$app" --threads 0
check "usage: unknown flag exits 1" 1 "--bogus" -- "$app" --bogus
check "--runs with trailing text" 1 "--runs: .*12:30" -- "$app" --table I --runs 12:30
check "NaN --delta-e is refused, not ignored" 1 "--delta-e: 'nan' is not a finite number" -- "$app" --table I --runs 1 --delta-e nan
check "infinite --delta-e" 1 "--delta-e: 'inf' is not a finite number" -- "$app" --table I --runs 1 --delta-e inf
check "--delta-eta with trailing text" 1 "--delta-eta: '1e-3abc' is not a number" -- \
  "$app" --data "$dir/good.csv" --u u --y y --r r --delta-eta 1e-3abc --delta-eps 1e-3
check "NaN --delta-eps" 1 "--delta-eps: 'nan' is not a finite number" -- \
  "$app" --data "$dir/good.csv" --u u --y y --r r --delta-eta 1e-3 --delta-eps nan
mkdir "$dir/k"
check "--json into a missing folder" 1 "--json .*does not exist" -- "$app" "${data[@]}" --json "$dir/k/no/out.json"
check_silent_stdout "--json checked before the work" "sets-lpv-pui: error: "
check_listing "nothing written beside a bad --json" "$dir/k"
"$app" --table II --runs 500 --threads 2 --json "$dir/k/t.json" >/dev/null 2>&1 &
pid=$!
sleep 0.5
kill -TERM $pid
wait $pid 2>/dev/null
[[ $? -eq 143 ]] || { echo "FAIL SIGTERM did not end the run"; fail=1; }
check_listing "SIGTERM during a run leaves nothing" "$dir/k"
exit $fail
