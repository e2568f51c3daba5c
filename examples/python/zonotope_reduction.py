#!/usr/bin/env python3
"""Order reduction of a zonotope: three methods, each result contains the original.

A 2-D zonotope with 20 generators is reduced to order 2 (4 generators) by Girard's,
Combastel's and the PCA method; the figure draws them over the original, and the script checks
on sampled points that each reduced zonotope contains the original.
    python3 examples/python/zonotope_reduction.py --out /tmp/figs
"""

from _common import setup

args = setup(__doc__.splitlines()[0])

import numpy as np  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

import sets  # noqa: E402
import sets.plot  # noqa: E402

rng = np.random.default_rng(3)
Z = sets.Zonotope(np.zeros(2), rng.normal(size=(2, 20)) * rng.uniform(0.05, 1.0, 20))
samples = (Z.generators @ rng.choice([-1.0, 1.0], size=(20, 2000))).T  # vertices of Z's cube


def area(v):
    x, y = v[:, 0], v[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))


fig, ax = plt.subplots(figsize=(6.5, 5.5))
base = area(sets.plot.polygon(Z))
print("original: %d generators, area %.3f" % (Z.num_generators, base))
styles = {"girard": "C0", "combastel": "C1", "pca": "C2"}
for name, color in styles.items():
    R = sets.reduce_order(Z, 2, getattr(sets.ReductionMethod, name))
    contained = all(sets.contains(R, p) != sets.BoolInterval.no for p in samples[:300])
    print("%-9s: %d generators, area %.3f (x%.2f), contains the sampled points: %s" % (
        name, R.num_generators, area(sets.plot.polygon(R)), area(sets.plot.polygon(R)) / base, contained))
    sets.plot.plot_set(R, ax=ax, fill=False, color=color, label="%s (order 2)" % name)
sets.plot.plot_set(Z, ax=ax, color="0.5", label="original (order 10)")
ax.set_aspect("equal")
ax.legend(loc="best", fontsize="small")
ax.set_title("zonotope order reduction: outer approximations")
fig.tight_layout()
path = "%s/zonotope_reduction.png" % args.out
fig.savefig(path, dpi=110)
print("figure:", path)
if args.show:
    plt.show()
