#!/usr/bin/env python3
"""Guaranteed parameter uncertainty intervals (PUIs) of an ARX model from bounded-error data.

    y(t) = a y(t-1) + b u(t-1) + e(t),   |e(t)| <= 0.05

Every (a, b) that explains all samples with |e| <= 0.05 forms the feasible parameter set (FPS),
an exact polygon here; its PUIs are the smallest box around it, each end certified by a safe
LP bound. The figure shows the box over the polygon and the true parameter.
    python3 examples/python/pui_example.py --out /tmp/figs
"""

from _common import setup

args = setup(__doc__.splitlines()[0])

import numpy as np  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

import sets  # noqa: E402
import sets.plot  # noqa: E402

rng = np.random.default_rng(1)
a, b, bound, N = 0.8, 0.5, 0.05, 200
u = rng.uniform(-1, 1, N)
y = np.zeros(N)
for t in range(1, N):
    y[t] = a * y[t - 1] + b * u[t - 1] + rng.uniform(-bound, bound)

Phi = np.column_stack([y[:-1], u[:-1]])          # regressors of y(1..N-1)
fps = sets.FeasibleParameterSet.from_data(Phi, y[1:], np.full(N - 1, bound))
r = sets.pui(fps)
print("PUIs (every end certified: %s)" % r.guaranteed)
for name, iv, true in zip(["a", "b"], r.box, [a, b]):
    print("  %s in [%.6f, %.6f]   true %.2f   inside: %s" % (name, iv.lo, iv.hi, true, iv.contains(true)))

fig, ax = plt.subplots(figsize=(6, 5))
sets.plot.plot_pui(fps, r, ax=ax, truth=[a, b])
ax.set_xlabel("a")
ax.set_ylabel("b")
ax.set_title("ARX, %d samples, |e| <= %g: FPS and its PUI box" % (N - 1, bound))
ax.legend(loc="best")
fig.tight_layout()
path = "%s/pui_example.png" % args.out
fig.savefig(path, dpi=110)
print("figure:", path)
if args.show:
    plt.show()
