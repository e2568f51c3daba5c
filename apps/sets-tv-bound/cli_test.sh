#!/usr/bin/env bash
# Command-line checks of sets-tv-bound's --input choice: bad values exit 1 and name the flag;
# each input is recorded in the JSON settings; the default stays the square wave; a prbs input
# depends on --input-seed and not on the noise --seed. Usage: cli_test.sh /path/to/sets-tv-bound
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

small=(--table I --case 0 --method linf --horizon 2)  # one LP on N = 40 samples
check "bad --input" 1 "--input" -- "$app" "${small[@]}" --input chirp
check "default input is square" 0 "input square" -- "$app" "${small[@]}" --json "$dir/sq.json"
grep -q '"kind": "square"' "$dir/sq.json" || { echo "FAIL square not recorded"; fail=1; }
check "prbs" 0 "input prbs" -- "$app" "${small[@]}" --input prbs --json "$dir/p1.json"
grep -q '"min_hold_s": 0.25' "$dir/p1.json" || { echo "FAIL prbs hold not recorded"; fail=1; }
check "multisine" 0 "input multisine" -- "$app" "${small[@]}" --input multisine --json "$dir/ms.json"
grep -q '"frequencies_rad_s"' "$dir/ms.json" || { echo "FAIL multisine frequencies not recorded"; fail=1; }

# The input changes the data, hence the deviation ||y - C zeta||_w; the prbs seed changes it too.
dev() { grep -o '"output_deviation_window_norm": [0-9.e+-]*' "$1"; }
check "prbs input seed 2" 0 "input prbs" -- "$app" "${small[@]}" --input prbs --input-seed 2 --json "$dir/p2.json"
check "prbs noise seed 2" 0 "input prbs" -- "$app" "${small[@]}" --input prbs --seed 2 --json "$dir/p3.json"
[[ "$(dev "$dir/sq.json")" != "$(dev "$dir/p1.json")" ]] || { echo "FAIL prbs data equal square data"; fail=1; }
[[ "$(dev "$dir/p1.json")" != "$(dev "$dir/p2.json")" ]] || { echo "FAIL --input-seed has no effect"; fail=1; }
# Same input seed, different noise seed: the sensitivities (noise-free) must be identical.
sens() { tr -d ' \n' <"$1" | grep -o '"sensitivity_window_norm":\[[^]]*\]'; }
[[ "$(sens "$dir/p1.json")" == "$(sens "$dir/p3.json")" ]] || { echo "FAIL noise --seed changed the prbs input"; fail=1; }

# ---- The exit-code and output contract (issue 12, point 4).
check "usage: unknown flag exits 1" 1 "--bogus" -- "$app" --bogus
check "usage: out-of-range --horizon" 1 "--horizon" -- "$app" "${small[@]}" --horizon 0
check "NaN --time-limit is refused at the flag (GLPK would abort)" 1 "--time-limit: 'nan' is not a finite number" -- \
  "$app" --table I --case 0 --method milp --horizon 2 --time-limit nan
check "infinite --time-limit" 1 "--time-limit: 'inf' is not a finite number" -- "$app" "${small[@]}" --time-limit inf
check "--mu with trailing text" 1 "--mu: '0.5abc' is not a number" -- "$app" "${small[@]}" --mu 0.5abc
check "--case with trailing text" 1 "--case: .*12:30" -- "$app" "${small[@]}" --case 12:30
check "--relinearise with the biaffine plant" 1 "--relinearise needs --plant exact" -- \
  "$app" "${small[@]}" --relinearise 1 --plant biaffine
mkdir "$dir/k"
check "--json into a missing folder" 1 "--json .*does not exist" -- "$app" "${small[@]}" --json "$dir/k/no/out.json"
check_silent_stdout "--json checked before the work" "sets-tv-bound: error: "
check_listing "nothing written beside a bad --json" "$dir/k"
"$app" --table I --method milp --horizon 6 --json "$dir/k/t.json" >/dev/null 2>&1 &
pid=$!
sleep 0.5
kill -TERM $pid
wait $pid 2>/dev/null
[[ $? -eq 143 ]] || { echo "FAIL SIGTERM did not end the run"; fail=1; }
check_listing "SIGTERM during a run leaves nothing" "$dir/k"
exit $fail
