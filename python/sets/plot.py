"""Plots for notebooks (matplotlib): 2-D projections of every set type, PUI boxes over the exact
feasible parameter set, and the diagnosis figures.

Every function takes an optional ``ax`` (a matplotlib Axes; default: the current one) and
returns what it drew, so calls compose::

    import sets, sets.plot
    ax = sets.plot.plot_set(Z, color="C0")
    sets.plot.plot_set(sets.reduce_order(Z, 2), ax=ax, color="C1", fill=False)

What a drawing means is stated with it: projections of zonotopes, V-polytopes and boxes are
exact (up to rounding), of ellipsoids a circumscribed polygon, of H-polytopes above 2-D the
intersection of certified supporting half-planes; all of them contain the true projection.
"""

import numpy as _np

from . import _sets

__all__ = ["polygon", "plot_set", "plot_pui", "fps_polygons", "plot_signals", "plot_signature", "plot_diagnosis",
           "save_report"]


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt
        ax = plt.gca()
    return ax


def polygon(s, dims=(0, 1), directions=64):
    """Vertices (k x 2, counter-clockwise) of a convex polygon that contains the projection of
    the set `s` onto coordinates `dims` (Box, Zonotope, Ellipsoid, HPolytope, VPolytope)."""
    i, j = dims
    if s.dimension == 2 and tuple(dims) == (0, 1) and isinstance(s, (_sets.Zonotope, _sets.VPolytope)):
        return _np.asarray(_sets.polygon_vertices(s)).T
    return _np.asarray(_sets.projection_polygon(s, i, j, directions)).T


def _draw_polygon(ax, v, fill, label, **style):
    from matplotlib.patches import Polygon
    style.setdefault("alpha", 0.35 if fill else 1.0)
    if fill:
        patch = Polygon(v, closed=True, fill=True, label=label, **style)
    else:
        style.setdefault("linewidth", 1.5)
        patch = Polygon(v, closed=True, fill=False, label=label, **style)
    ax.add_patch(patch)
    ax.update_datalim(v)
    ax.autoscale_view()
    return patch


def plot_set(s, ax=None, dims=(0, 1), fill=True, label=None, directions=64, **style):
    """Draws the 2-D projection of a set (see polygon()) as a matplotlib patch and returns it."""
    ax = _axes(ax)
    v = polygon(s, dims, directions)
    if len(v) == 1:  # a point
        return ax.plot(v[:, 0], v[:, 1], "o", label=label, **style)[0]
    return _draw_polygon(ax, v, fill, label, **style)


def fps_polygons(fps, dims=(0, 1), result=None):
    """The feasible parameter set projected on `dims` as a list of convex polygons (k x 2).

    Two parameters: each orthant piece is the exact polygon (vertices computed in exact
    arithmetic by CGAL, rounded to nearest). More parameters: each orthant piece is projected
    through certified support values (an outer polygon). Exact regressors give one piece;
    interval regressors one per orthant that the PUI computation found feasible (``result``,
    computed with OrthantSelection.all if not given)."""
    if result is None:
        opts = _sets.PuiOptions(orthants=_sets.OrthantSelection.all) if fps.has_interval_regressors else _sets.PuiOptions()
        result = _sets.pui(fps, opts)
    pieces = []
    for rep in result.orthants:
        if rep.status != _sets.OrthantStatus.feasible:
            continue
        P = fps.orthant_polytope(list(rep.signs))
        if not _np.all(_np.isfinite(_np.asarray(rep.box.to_array()))):
            # An unbounded piece cannot be drawn as a polygon: clip it to the PUI box (drawn too).
            P = _sets.intersect(P, _sets.to_hpolytope(result.box))
        if fps.dimension == 2:
            try:
                pieces.append(_np.asarray(_sets.polygon_vertices(P)).T)
                continue
            except (_sets.UnsupportedError, _sets.EmptySetError):
                pass
        try:
            pieces.append(_np.asarray(_sets.projection_polygon(P, dims[0], dims[1], 64)).T)
        except _sets.EmptySetError:
            pass
    return pieces


def plot_pui(fps, result=None, ax=None, dims=(0, 1), truth=None, label_set="feasible parameter set",
             label_box="PUI box", **style):
    """PUI box (dashed) over the feasible parameter set (filled polygons: exact in 2-D) on the
    parameters `dims`; `truth` (optional) marks the true parameter. Returns the PuiResult."""
    ax = _axes(ax)
    if result is None:
        opts = _sets.PuiOptions(orthants=_sets.OrthantSelection.all) if fps.has_interval_regressors else _sets.PuiOptions()
        result = _sets.pui(fps, opts)
    if result.empty:
        ax.set_title("the data falsify the model: " + result.falsification.message())
        return result
    color = style.pop("color", "C0")
    for k, v in enumerate(fps_polygons(fps, dims, result)):
        _draw_polygon(ax, v, True, label_set if k == 0 else None, color=color, **style)
    b = result.box.to_array()[list(dims)]
    from matplotlib.patches import Rectangle
    if _np.all(_np.isfinite(b)):
        rect = Rectangle((b[0, 0], b[1, 0]), b[0, 1] - b[0, 0], b[1, 1] - b[1, 0], fill=False, linestyle="--",
                         edgecolor="k", linewidth=1.5,
                         label=label_box + ("" if result.guaranteed else " (not certified)"))
        ax.add_patch(rect)
        ax.update_datalim(b.T)
    if truth is not None:
        ax.plot([truth[dims[0]]], [truth[dims[1]]], "k*", markersize=10, label="true value")
    ax.autoscale_view()
    ax.set_xlabel("theta_%d" % (dims[0] + 1))
    ax.set_ylabel("theta_%d" % (dims[1] + 1))
    return result


# ------------------------------------------------------------------------- diagnosis figures

def _unit_lookup(diagnosis, units):
    """name -> unit: the user's dict if given, else the model file's `units` (an output column
    shares its symbol's unit)."""
    if units is not None:
        return lambda name: units.get(name, "")
    return diagnosis.nominal_model.unit


def _label(unit_of, name):
    u = unit_of(name)
    return "%s [%s]" % (name, u) if u else name


def plot_signals(diagnosis, record="estimation", units=None, fig=None):
    """Measured, calibrated nominal and augmented outputs of one record with, under each output,
    its residuals (measured - nominal, measured - augmented); the mismatch windows are shaded.
    `units` maps recording columns to units (default: the model file's `units`)."""
    import matplotlib.pyplot as plt
    unit_of = _unit_lookup(diagnosis, units)
    s = diagnosis.signals
    t = s["time_" + record]
    meas, nom, aug = s["measured_" + record], s["nominal_" + record], s["augmented_" + record]
    outs = diagnosis.outputs
    fig = fig or plt.figure(figsize=(10, 3.2 * len(outs)))
    axes = fig.subplots(2 * len(outs), 1, sharex=True, gridspec_kw={"height_ratios": [3, 1.4] * len(outs)})
    for j, name in enumerate(outs):
        ax, axr = axes[2 * j], axes[2 * j + 1]
        ax.plot(t, meas[:, j], color="k", lw=1.6, label="measured")
        ax.plot(t, nom[:, j], color="tab:red", lw=1, label="nominal (calibrated)")
        ax.plot(t, aug[:, j], color="tab:blue", lw=1, label="augmented")
        axr.plot(t, meas[:, j] - nom[:, j], color="tab:red", lw=0.8, label="measured - nominal")
        axr.plot(t, meas[:, j] - aug[:, j], color="tab:blue", lw=0.8, label="measured - augmented")
        if record == "estimation":
            for w in diagnosis["mismatch"]["windows"]:
                if w["output"] == name:
                    for a in (ax, axr):
                        a.axvspan(w["start"], w["end"], color="#ffb0b0", alpha=0.45, lw=0)
        ax.set_ylabel(_label(unit_of, name))
        axr.set_ylabel("residual" + (" [%s]" % unit_of(name) if unit_of(name) else ""))
        ax.grid(True, alpha=0.3)
        axr.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("t [s]")
    fig.suptitle("%s record: measured, nominal and augmented%s" % (
        record, "; shaded: mismatch windows" if record == "estimation" else ""))
    return fig


def plot_signature(diagnosis, units=None, ax=None):
    """The residual of the first output (measured - calibrated nominal) against the variable
    that explains it best, with the fitted term of the first effect found drawn over it."""
    ax = _axes(ax)
    unit_of = _unit_lookup(diagnosis, units)
    s = diagnosis.signals
    x, r = _np.asarray(s["signature_x"]), _np.asarray(s["signature_residual"])
    ax.plot(x, r, ".", ms=2, color="0.4", label="residual")
    out = s["signature_output"]
    if diagnosis["effects"] and out in diagnosis.outputs:
        # The effect as it shows in this output: augmented - nominal at the same samples. (The
        # term itself lives in an equation of the model, in that equation's units.)
        j = diagnosis.outputs.index(out)
        term = s["augmented_estimation"][:, j] - s["nominal_estimation"][:, j]
        if len(term) == len(x):
            order = _np.argsort(x, kind="stable")
            ax.plot(x[order], term[order], ".", ms=2, color="tab:blue",
                    label="fitted: augmented - nominal (%s)" % ", ".join(e["name"] for e in diagnosis["effects"]))
    var = s["signature_variable"]
    ax.set_xlabel(_label(unit_of, var))
    ax.set_ylabel("residual of " + _label(unit_of, out))
    ax.set_title("signature: residual of %s against %s" % (out, var))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_diagnosis(diagnosis, units=None):
    """Every figure of the report: signals of each record and the signature. Returns the list
    of figures."""
    import matplotlib.pyplot as plt
    figs = [plot_signals(diagnosis, "estimation", units)]
    if diagnosis.data.has_validation:
        figs.append(plot_signals(diagnosis, "validation", units))
    fig = plt.figure(figsize=(8, 5))
    plot_signature(diagnosis, units, fig.gca())
    figs.append(fig)
    return figs


def save_report(diagnosis, folder, units=None, dpi=100):
    """Writes the diagnosis as sets-diagnose --report does, with the matplotlib figures:
    folder/index.html (self-contained page), the PNGs beside it, report.txt and
    augmented_model.json. Returns the path of index.html."""
    import os
    import matplotlib.pyplot as plt
    os.makedirs(folder, exist_ok=True)
    names = ["signals_estimation"] + (["signals_validation"] if diagnosis.data.has_validation else []) + ["signature"]
    captions = {
        "signals_estimation": "The estimation record: measured, calibrated nominal and augmented outputs; under each, "
                              "the residuals; shaded: the mismatch windows.",
        "signals_validation": "The validation record: measured, calibrated nominal and augmented outputs; under each, "
                              "the residuals.",
        "signature": "Signature: the residual against the variable that explains it best, with the effects found "
                     "(augmented - nominal) over it.",
    }
    figures = []
    for name, fig in zip(names, plot_diagnosis(diagnosis, units)):
        fig.savefig(os.path.join(folder, name + ".png"), dpi=dpi)
        plt.close(fig)
        figures.append((name + ".png", captions[name]))
    with open(os.path.join(folder, "report.txt"), "w") as f:
        f.write(diagnosis.text)
    diagnosis.augmented_model.save(os.path.join(folder, "augmented_model.json"))
    path = os.path.join(folder, "index.html")
    with open(path, "w", encoding="utf-8") as f:
        f.write(diagnosis.data.html(figures))
    return path
