#!/bin/sh
# Regenerates the table of docs/reproduction/hakvoort.md: the bound against N and against the
# tail prior rho (stochastic noise, built-in example, 20 Monte Carlo runs per row).
set -e
APP=${APP:-./build/apps/sets-hinf-bound/sets-hinf-bound}
OUT=${OUT:-/tmp/hakvoort_table}
mkdir -p "$OUT"
for N in 1000 2000 5000 10000; do
  $APP --N $N --runs 20 --quiet --json "$OUT/N$N.json" > "$OUT/N$N.txt"
  $APP --N $N --runs 20 --quiet --nominal-order 4 --json "$OUT/N${N}_nom4.json" > "$OUT/N${N}_nom4.txt"
done
for rho in 0.86 0.9 0.93 0.96; do
  $APP --N 2000 --runs 20 --quiet --rho $rho --json "$OUT/rho$rho.json" > "$OUT/rho$rho.txt"
done
