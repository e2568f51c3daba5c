#!/usr/bin/env bash
# Command-line checks of sets-demo: the exit-code contract of docs/contributing.md (issue 12,
# point 4): usage errors exit 1, numbers are parsed whole, NaN and infinity are refused.
# Usage: cli_test.sh /path/to/sets-demo
set -u
app="$1"
source "$(dirname "$0")/../../tests/support/cli_check.sh"

check "default run" 0 "certified by a safe \(Neumaier-Shcherbina\) bound: yes" -- "$app"
check "--help" 0 "--samples" -- "$app" --help
check "unknown flag" 1 "--bogus" -- "$app" --bogus
check "out-of-range number" 1 "--samples" -- "$app" --samples 5
check "integer with trailing text" 1 "--samples: .*12:30" -- "$app" --samples 12:30
check "number with trailing text" 1 "--noise: '0.5abc' is not a number" -- "$app" --noise 0.5abc
check "NaN" 1 "--noise: 'nan' is not a finite number" -- "$app" --noise nan
check "infinity" 1 "--noise: 'inf' is not a finite number" -- "$app" --noise inf
check "negative seed" 1 "--seed: '-1' is not a whole non-negative number" -- "$app" --seed -1
check "hexadecimal" 1 "--seed: '0x10' is not a whole" -- "$app" --seed 0x10
check "leading zeros are decimal, not octal" 0 "N = 10 samples" -- "$app" --samples 010
exit $fail
