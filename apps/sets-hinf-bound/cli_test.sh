#!/usr/bin/env bash
# Command-line checks of sets-hinf-bound: exit codes (docs/contributing.md: 0 success, 1 bad input
# or usage, 2 data falsify the priors, 3 numerical failure) and that each message names the
# problem. Usage: cli_test.sh /path/to/sets-hinf-bound
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

# A small FIR system y(t) = 0.5 u(t-1) + 0.25 u(t-2) + 0.125 u(t-3) + v(t), |v| <= 0.01, u in [-1, 1]
# (awk: no Python needed). Priors for a 10-tap FIR basis: |g(k)| <= 1 * 0.88^k (the default rho) holds.
awk 'BEGIN {
  srand(5); T = 400; print "t,u,y";
  u1 = 0; u2 = 0; u3 = 0;
  for (t = 1; t <= T; ++t) {
    u = 2 * rand() - 1;
    printf "%d,%.17g,%.17g\n", t, u, 0.5 * u1 + 0.25 * u2 + 0.125 * u3 + 0.01 * (2 * rand() - 1);
    u3 = u2; u2 = u1; u1 = u;
  }
}' >"$dir/good.csv"
fir=(--basis fir --order 10 --M 1 --u-bar 0 --grid 20 --weight-degree 4 --quiet)
good=(--data "$dir/good.csv" --u u --y y "${fir[@]}")

check "good data, bounded noise" 0 "b = " -- "$app" "${good[@]}" --noise bounded --v-bar 0.01 --json "$dir/out.json"
grep -q '"noise": "bounded"' "$dir/out.json" || { echo "FAIL json output"; fail=1; }
# The data-based bound is reported as a number (nlohmann writes inf as null).
grep -qE '"b_data": [0-9]' "$dir/out.json" || { echo "FAIL json b_data"; fail=1; }

# Usage errors (CLI11) exit 1, not CLI11's own codes.
check "unknown flag" 1 "--bogus" -- "$app" --bogus
check "--N out of range" 1 "--N" -- "$app" --N 5
check "bad --noise" 1 "--noise" -- "$app" --noise loud
check "bad --basis" 1 "--basis" -- "$app" --basis wavelet

# Bad priors and grid (library InputError).
check "rho >= 1" 1 "rho = 1.2.*0 < rho < 1" -- "$app" "${good[@]}" --rho 1.2
check "grid above pi" 1 "frequency grid: w\[.*" -- "$app" "${good[@]}" --w-max 4
check "alpha outside (0, 1)" 1 "alpha = 1.5" -- "$app" "${good[@]}" --alpha 1.5
check "nominal order cannot be met" 1 "nominal order 30 cannot be met" -- "$app" "${good[@]}" --nominal-order 30
check "missing --M with data" 1 "--M" -- "$app" --data "$dir/good.csv" --u u --y y --basis fir --order 10 --quiet
check "missing --v-bar with data" 1 "--v-bar" -- "$app" "${good[@]}" --noise bounded

# Bad data files name the file, line and column.
check "missing file" 1 "nothere.csv: cannot open" -- "$app" --data "$dir/nothere.csv" --u u --y y "${fir[@]}"
sed '41s/^\([0-9]*\),\([^,]*\),.*/\1,\2,nan/' "$dir/good.csv" >"$dir/nan.csv"
check "NaN sample" 1 "nan.csv: data row 40 \(line 41\), column \"y\": NaN or infinite value" -- \
  "$app" --data "$dir/nan.csv" --u u --y y "${fir[@]}"
sed '41s/$/,7/' "$dir/good.csv" >"$dir/ragged.csv"
check "ragged row" 1 "ragged.csv: line 41: more than 3 values" -- "$app" --data "$dir/ragged.csv" --u u --y y "${fir[@]}"
check "unknown column" 1 "good.csv: no column \"x\" \(given by --u\)" -- "$app" --data "$dir/good.csv" --u x --y y "${fir[@]}"
head -30 "$dir/good.csv" >"$dir/short.csv"
check "too few samples" 1 "too few for 10 basis functions" -- "$app" --data "$dir/short.csv" --u u --y y "${fir[@]}"

# A noise bound far below the true one: the data falsify the priors (exit 2).
check "falsified priors" 2 "falsify" -- "$app" "${good[@]}" --noise bounded --v-bar 1e-4

# Output files are written completely or not at all.
check "unwritable JSON path" 1 "out.json: cannot write" -- \
  "$app" "${good[@]}" --noise bounded --v-bar 0.01 --json "$dir/no/such/dir/out.json"
[[ ! -e "$dir/no/such/dir/out.json" ]] || { echo "FAIL partial JSON written"; fail=1; }

# ---- The exit-code and output contract (issue 12, point 4).
# Numbers in the data are read whole; binary garbage is not echoed raw to the terminal.
sed '41s/^\([0-9]*\),[^,]*,/\1,0.5abc,/' "$dir/good.csv" >"$dir/abc.csv"
check "data: a number with trailing text" 1 "abc.csv: line 41, column 2 \(\"u\"\): not a number: \"0.5abc\"" -- \
  "$app" --data "$dir/abc.csv" --u u --y y "${fir[@]}"
sed '41s/^\([0-9]*\),[^,]*,/\1,12:30,/' "$dir/good.csv" >"$dir/time.csv"
check "data: a time of day" 1 "time.csv: line 41, column 2 \(\"u\"\): not a number: \"12:30\"" -- \
  "$app" --data "$dir/time.csv" --u u --y y "${fir[@]}"
{ head -40 "$dir/good.csv"; printf '40,\x1b[2J\x07\xff\xfe,0.1\n'; } >"$dir/garbage.csv"
check "data: binary garbage" 1 "garbage.csv: line 41, column 2" -- "$app" --data "$dir/garbage.csv" --u u --y y "${fir[@]}"
check_printable "binary garbage is escaped in the message"
check "header-less file, columns by number" 0 "b = " -- "$app" --data <(tail -n +2 "$dir/good.csv") --u 2 --y 3 "${fir[@]}"

check "out-of-range number" 1 "--N" -- "$app" --N 5
check "number with trailing text" 1 "--alpha: '0.5abc' is not a number" -- "$app" "${good[@]}" --alpha 0.5abc
check "integer with trailing text" 1 "--runs: .*12:30" -- "$app" "${good[@]}" --runs 12:30
check "hexadecimal integer" 1 "--grid: '0x10' is not a whole" -- "$app" "${good[@]}" --grid 0x10
check "NaN noise bound is refused at the flag" 1 "--v-bar: 'nan' is not a finite number" -- \
  "$app" "${good[@]}" --noise bounded --v-bar nan
check "infinite prior" 1 "--M: 'inf' is not a finite number" -- "$app" "${good[@]}" --M inf
check "overflowing number" 1 "--rho: '1e400' is out of the range" -- "$app" "${good[@]}" --rho 1e400
check "leading zeros are decimal, not octal" 0 "n = 10 functions" -- "$app" --runs 1 --quiet --order 010

# Output paths are checked before the work: a missing folder exits 1, prints no results and
# leaves nothing behind (here or in the temporary folder).
mkdir "$dir/k"
ls /tmp | grep '^sets-hinf-' | sort >"$dir/tmp_before"
check "--plot into a missing folder" 1 "--plot .*cannot write there: the folder .* does not exist" -- \
  "$app" "${good[@]}" --noise bounded --v-bar 0.01 --json "$dir/k/out.json" --plot "$dir/k/no/plot.png"
check_silent_stdout "--plot checked before the work" "sets-hinf-bound: error: "
check_listing "nothing written beside a bad --plot" "$dir/k"
ls /tmp | grep '^sets-hinf-' | sort | diff -q - "$dir/tmp_before" >/dev/null || { echo "FAIL temporary folder left in /tmp"; fail=1; }
check "--json into a missing folder" 1 "--json .*does not exist" -- "$app" "${good[@]}" --json "$dir/k/no/out.json"
check_silent_stdout "--json checked before the work" "sets-hinf-bound: error: "
check "--json is a folder" 1 "--json .*it is a folder" -- "$app" "${good[@]}" --json "$dir/k"
check "--plot written" 0 "b = " -- "$app" "${good[@]}" --plot "$dir/k/plot.png"
check_listing "only the plot is left" "$dir/k" plot.png
rm -f "$dir/k/plot.png"

# Killed while plotting: SIGTERM removes the temporaries (and gnuplot); a temporary left by SIGKILL
# is removed by the next run that writes the same plot.
if signal_during TERM "$dir/k/.plot.png.sets-tmp.*" -- "$app" --runs 1 --quiet --plot "$dir/k/plot.png"; then
  [[ $signal_status -eq 143 ]] || { echo "FAIL SIGTERM: status $signal_status"; fail=1; }
  check_listing "SIGTERM while plotting leaves nothing" "$dir/k"
else
  echo "FAIL SIGTERM: the plot's temporary never appeared (status $signal_status)"; fail=1
fi
if signal_during KILL "$dir/k/.plot.png.sets-tmp.*" -- "$app" --runs 1 --quiet --plot "$dir/k/plot.png"; then
  sleep 1  # gnuplot, orphaned, finishes
  compgen -G "$dir/k/.plot.png.sets-tmp.*" >/dev/null || { echo "FAIL SIGKILL left no temporary (test not meaningful)"; fail=1; }
  check "next run after SIGKILL" 0 "b = " -- "$app" "${good[@]}" --plot "$dir/k/plot.png"
  check_listing "the stale temporary is removed by the next run" "$dir/k" plot.png
else
  echo "FAIL SIGKILL: the plot's temporary never appeared"; fail=1
fi
exit $fail
