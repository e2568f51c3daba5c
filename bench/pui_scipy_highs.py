#!/usr/bin/env python3
"""PUIs of the Cerone-Regruto N = 1000 problem with scipy's HiGHS, for the side-by-side figure.

The polytope comes from the C++ benchmark (the orthant piece that pui() visits):

    SETS_DUMP_LPV_POLYTOPE=/tmp/lpv.txt build/bench/lpv_pui_bench --benchmark_filter=none
    /usr/bin/python3 bench/pui_scipy_highs.py /tmp/lpv.txt [repetitions]

It solves the 2p LPs min/max theta_l over {a^T theta <= b} with linprog(method='highs'), all rows
at once (what one would write without row generation), reports the median wall and CPU time of
the 2p solves and the largest difference from the C++ PUI ends (which are certified outward
bounds, so they should lie at or just outside HiGHS' floating-point optima).
"""
import statistics
import sys
import time

import numpy as np
from scipy.optimize import linprog


def main() -> None:
    path = sys.argv[1]
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    rows, ends = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("# pui"):
                ends.append([float(v) for v in line.split()[2:4]])
            elif line.strip():
                rows.append([float(v) for v in line.split()])
    data = np.array(rows)
    A, b = data[:, :-1], data[:, -1]
    p = A.shape[1]
    walls, cpus, box = [], [], None
    for _ in range(reps):
        w0, c0 = time.perf_counter(), time.process_time()
        box = []
        for l in range(p):
            ends_l = []
            for sign in (1.0, -1.0):
                c = np.zeros(p)
                c[l] = sign
                r = linprog(c, A_ub=A, b_ub=b, bounds=[(None, None)] * p, method="highs")
                if r.status != 0:
                    raise SystemExit(f"HiGHS: {r.message}")
                ends_l.append(sign * r.fun)
            box.append(ends_l)
        walls.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
    diff = max(max(abs(lo - e[0]), abs(hi - e[1])) for (lo, hi), e in zip(box, ends))
    outward = all(e[0] <= lo + 1e-12 * (1 + abs(lo)) and e[1] >= hi - 1e-12 * (1 + abs(hi)) for (lo, hi), e in zip(box, ends))
    print(f"{A.shape[0]} rows, p = {p}: {2 * p} HiGHS LPs, median of {reps}: "
          f"{1e3 * statistics.median(walls):.1f} ms wall, {1e3 * statistics.median(cpus):.1f} ms CPU")
    print(f"largest |HiGHS end - sets end| = {diff:.3g}; sets ends outside HiGHS' optima: {outward}")


if __name__ == "__main__":
    main()
