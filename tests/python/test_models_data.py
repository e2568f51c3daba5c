"""Model files and recordings: columns as numpy arrays, exact CSV round trip, the simulator,
errors naming the file, line and field."""

import numpy as np
import pytest

import sets

MODEL = """{
  "name": "mass on a spring",
  "time": "t",
  "inputs": {"u": "u"},
  "parameters": {"k": 2.0, "c": {"value": 0.3, "fixed": true}},
  "states": {"x": 0.0, "v": 0.0},
  "derivatives": {"x": "v", "v": "u - k*x - c*v"},
  "outputs": {"x": "x_meas"}
}"""


def recording(N=200):
    t = np.arange(N) * 0.01
    return sets.Recording({"t": t, "u": np.sin(3 * t), "x_meas": np.zeros(N)}, "mem.csv")


def test_recording_columns_are_numpy_arrays_and_csv_round_trips(tmp_path):
    r = recording()
    assert r.rows == 200 and r.names == ["t", "u", "x_meas"] and "u" in r
    assert isinstance(r["u"], np.ndarray) and r["u"].dtype == np.float64
    sets.write_csv(r, str(tmp_path / "r.csv"))
    back = sets.read_csv(str(tmp_path / "r.csv"))
    for n in r.names:
        # write_csv writes 12 significant digits (a lossy round trip, see docs/python.md)
        np.testing.assert_allclose(back[n], r[n], rtol=1e-11, atol=1e-300)
    with pytest.raises(KeyError):
        r["nope"]
    with pytest.raises(sets.InputError, match="nope"):
        r.column("nope")


def test_csv_errors_name_the_line(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("a,b\n1,2\n3,x\n")
    with pytest.raises(sets.InputError, match=r"bad\.csv.*line 3"):
        sets.read_csv(str(p))


def test_model_file_parse_simulate_and_save(tmp_path):
    m = sets.ModelFile.parse(MODEL, "spring.json")
    assert [p.name for p in m.parameters] == ["k", "c"] and m.parameter("c").fixed
    sim = sets.Simulator(m, recording())
    res = sim.simulate(sim.parameter_values)
    x = res.series("x")
    # the response to sin(3t) from rest: small, smooth, finite
    assert np.all(np.isfinite(x)) and 0 < np.max(np.abs(x)) < 1
    np.testing.assert_array_equal(res.outputs[:, 0], x)
    assert m.unit("x") == "" and m.unit("t") == "s"
    m.units = [("x", "m")]
    assert m.unit("x_meas") == "m"  # the output column shares its symbol's unit
    m.save(str(tmp_path / "m.json"))
    back = sets.ModelFile.load(str(tmp_path / "m.json"))
    assert back.to_json_text() == m.to_json_text()


def test_model_errors_name_line_and_field():
    with pytest.raises(sets.InputError, match="line"):
        sets.ModelFile.parse('{"name": "x",\n "time": }', "broken.json")
    with pytest.raises(sets.InputError, match=r'typo\.json: unknown field "derivates"'):
        sets.ModelFile.parse(MODEL.replace('"derivatives"', '"derivates"'), "typo.json")
    with pytest.raises(sets.InputError, match=r"units\.speed"):
        sets.ModelFile.parse(MODEL.replace('"outputs"', '"units": {"speed": "m/s"}, "outputs"'), "units.json")
    m = sets.ModelFile.parse(MODEL.replace("u - k*x", "u - kk*x"), "unknown.json")
    with pytest.raises(sets.InputError, match="kk"):
        sets.Simulator(m, recording())
