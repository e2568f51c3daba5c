"""diagnose() returns the structure of the JSON of sets-diagnose, with the same values."""

import json

import numpy as np

import sets


def strip_timing(d):
    d = dict(d)
    d.pop("seconds", None)
    d["augmented"] = dict(d["augmented"], model=None)
    return d


def test_diagnose_equals_the_app_on_the_built_in_example(tmp_path, app):
    app("sets-diagnose", "--example", "--quiet", "--json", tmp_path / "d.json")
    expected = json.loads((tmp_path / "d.json").read_text())
    plant = sets.examples.synthetic_plant("coulomb_friction")
    lines = []
    d = sets.diagnose(plant.nominal, plant.estimation, plant.validation, threads=2, progress=lines.append)
    assert isinstance(d, dict)
    assert strip_timing(d) == strip_timing(expected)
    assert lines, "the progress callback was called"
    assert d["effects"] and d["effects"][0]["name"] == "coulomb_friction"
    # signals for plots: one row per sample, one column per output
    s = d.signals
    assert s["measured_estimation"].shape == (len(s["time_estimation"]), len(d.outputs))
    assert len(s["signature_x"]) == len(s["signature_residual"])
    assert "Verdict" in d.text
    assert d.augmented_model.parameter("Fc").value != 0
    # the guaranteed interval of the friction contains its true value (0.3 N)
    lo, hi = d["effects"][0]["parameters"]["Fc"]["interval"]
    assert lo <= dict(plant.true_values)["Fc"] <= hi
