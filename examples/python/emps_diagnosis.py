#!/usr/bin/env python3
"""Discrepancy diagnosis of the EMPS positioning axis (real recordings, ../shared/data/emps).

The nominal model has viscous friction only; the diagnosis calibrates it, locates where it
fails, names the missing physics (friction and an offset on this axis), adds it and refits.
Prints the report and writes the figures (signals with residual panels, signature).
Skips with a message when the recordings are absent (set SETS_SHARED_DIR).
    python3 examples/python/emps_diagnosis.py --out /tmp/figs
"""

import sys

from _common import setup, shared_dir

args = setup(__doc__.splitlines()[0])

import matplotlib.pyplot as plt  # noqa: E402

import sets  # noqa: E402
import sets.plot  # noqa: E402

emps = shared_dir() / "data" / "emps"
if not (emps / "nominal.json").exists():
    print("skipped: no EMPS recordings at %s (set SETS_SHARED_DIR to the folder holding data/emps)" % emps)
    sys.exit(0)

d = sets.diagnose(str(emps / "nominal.json"), str(emps / "estimation.csv"), str(emps / "validation.csv"),
                  threads=2, progress=lambda s: print("  [diagnose]", s, flush=True))
print(d.text)
print("verdict:", d["verdict"])
for e in d["effects"]:
    for name, p in e["parameters"].items():
        print("  %s: %s = %.5g, guaranteed interval [%s, %s]" % (e["name"], name, p["estimate"], *p["interval"]))
for k, fig in enumerate(sets.plot.plot_diagnosis(d)):
    name = ["signals_estimation", "signals_validation", "signature"][k if d.data.has_validation else 2 * k]
    fig.savefig("%s/emps_%s.png" % (args.out, name), dpi=100)
    print("figure: %s/emps_%s.png" % (args.out, name))
if args.show:
    plt.show()
