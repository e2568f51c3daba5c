"""sets: guaranteed set-membership system identification (Python bindings of the C++ library).

Sets that are guaranteed to contain the true system -- outward-rounded intervals and boxes,
zonotopes, ellipsoids, H- and V-polytopes, feasible parameter sets with certified parameter
uncertainty intervals (PUIs) -- the four papers' methods, and the discrepancy diagnosis.

    import numpy as np, sets
    fps = sets.FeasibleParameterSet.from_data(Phi, y, delta)   # |y - Phi theta| <= delta
    r = sets.pui(fps)
    r.box.lower, r.box.upper, r.guaranteed                     # PUIs, certified?

Submodules: sets.plot (matplotlib), sets.campaign (Monte Carlo studies on Dask),
sets.examples (the papers' example systems, the synthetic plants). See docs/python.md.
"""

import json as _json
import sys as _sys

from . import _sets
from ._sets import *  # noqa: F401,F403  (the compiled API)
from ._sets import Error, InputError, NumericalError, UnsupportedError, EmptySetError  # noqa: F401

examples = _sets.examples
_sys.modules[__name__ + ".examples"] = examples

__all__ = [n for n in dir(_sets) if not n.startswith("_")] + ["diagnose", "Diagnosis", "box"]


def box(lower, upper):
    """The box [lower, upper] (1-D arrays of equal length)."""
    return Box(lower, upper)


class Diagnosis(dict):
    """The result of diagnose(): a dict with the structure of `sets-diagnose --json`
    (keys "nominal", "mismatch", "effects", "augmented", "verdict", ...), plus

    - ``signals``: numpy arrays for plots (time, measured/nominal/augmented outputs of the
      estimation and validation records, the signature's x and residual);
    - ``augmented_model`` / ``nominal_model``: the calibrated model files (ModelFile);
    - ``text``: the terminal report; ``data``: the C++ object (DiagnosisData).
    """

    def __init__(self, data):
        super().__init__(_json.loads(data.json_text("")))
        self.data = data
        self.text = data.text()
        self.augmented_model = data.augmented
        self.nominal_model = data.nominal
        self.outputs = list(data.outputs)
        self.signals = {
            name: getattr(data, name)
            for name in ("time_estimation", "measured_estimation", "nominal_estimation", "augmented_estimation",
                         "time_validation", "measured_validation", "nominal_validation", "augmented_validation",
                         "signature_x", "signature_residual")
        }
        self.signals["signature_variable"] = data.signature_variable
        self.signals["signature_output"] = data.signature_output

    def json_text(self, augmented_path=""):
        """The JSON text sets-diagnose writes (``augmented_path`` goes into "augmented.model")."""
        return self.data.json_text(augmented_path)


def diagnose(model, data, validation=None, options=None, **option_fields):
    """Discrepancy diagnosis: calibrate `model` (a ModelFile or a path) on `data` (a Recording or
    a path), locate where it fails, name the missing physics, add it and refit; `validation`
    (optional) judges the hypotheses. Returns a Diagnosis (a dict shaped like the JSON of
    sets-diagnose). Keyword arguments set DiagnosisOptions fields (e.g. threads=2,
    progress=print). The GIL is released while it runs."""
    if isinstance(model, str):
        model = ModelFile.load(model)
    if isinstance(data, str):
        data = read_recording(data)
    if isinstance(validation, str):
        validation = read_recording(validation)
    if options is None:
        options = DiagnosisOptions(**option_fields)
    else:
        for k, v in option_fields.items():
            setattr(options, k, v)
    return Diagnosis(_sets._diagnose(model, data, validation, options))
