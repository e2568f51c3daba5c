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
check "NaN sample" 1 "nan.csv:41: column 3 \(y\): 'nan' is not a finite number" -- \
  "$app" --data "$dir/nan.csv" --u u --y y "${fir[@]}"
sed '41s/$/,7/' "$dir/good.csv" >"$dir/ragged.csv"
check "ragged row" 1 "ragged.csv:41: 4 fields, expected 3" -- "$app" --data "$dir/ragged.csv" --u u --y y "${fir[@]}"
check "unknown column" 1 "no column 'x'" -- "$app" --data "$dir/good.csv" --u x --y y "${fir[@]}"
head -30 "$dir/good.csv" >"$dir/short.csv"
check "too few samples" 1 "too few for 10 basis functions" -- "$app" --data "$dir/short.csv" --u u --y y "${fir[@]}"

# A noise bound far below the true one: the data falsify the priors (exit 2).
check "falsified priors" 2 "falsify" -- "$app" "${good[@]}" --noise bounded --v-bar 1e-4

# Output files are written completely or not at all.
check "unwritable JSON path" 1 "out.json: cannot write" -- \
  "$app" "${good[@]}" --noise bounded --v-bar 0.01 --json "$dir/no/such/dir/out.json"
[[ ! -e "$dir/no/such/dir/out.json" ]] || { echo "FAIL partial JSON written"; fail=1; }
exit $fail
