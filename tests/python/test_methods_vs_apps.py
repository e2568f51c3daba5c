"""The Python entry points give the same numbers as the apps on the same inputs: data written to
a CSV with 17 significant digits (exact round trip), the app's --json against the binding."""

import json

import numpy as np
import pytest

import sets


def write_csv(path, columns):
    names = list(columns)
    data = np.column_stack([columns[n] for n in names])
    np.savetxt(path, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")


def test_lpv_pui_equals_the_app(tmp_path, app):
    rng = np.random.default_rng(11)
    structure = sets.examples.cerone_regruto_structure()
    theta = np.array([0.5, -0.2, 0.3, 0.1, 1.0, 0.2])
    T = 150
    u = rng.uniform(-1, 1, T)
    lam = rng.uniform(-1, 1, (T, 1))
    w = sets.simulate_lpv(structure, theta, u, lam)
    d_eta, d_eps = 0.05, 0.02
    y = w + rng.uniform(-d_eta, d_eta, T)
    r = lam[:, 0] + rng.uniform(-d_eps, d_eps, T)
    write_csv(tmp_path / "lpv.csv", {"u": u, "y": y, "r": r})
    app("sets-lpv-pui", "--data", tmp_path / "lpv.csv", "--u", "u", "--y", "y", "--r", "r", "--delta-eta", d_eta,
        "--delta-eps", d_eps, "--json", tmp_path / "lpv.json")
    expected = json.loads((tmp_path / "lpv.json").read_text())
    data = sets.LpvMeasurements(u=u, y=y, r=r[:, None], delta_eta=np.array([d_eta]), delta_eps=np.array([[d_eps]]))
    res = sets.lpv_pui(structure, data)
    assert res.pui.guaranteed == expected["guaranteed"]
    assert [p["name"] for p in expected["parameters"]] == structure.parameter_names
    for k, p in enumerate(expected["parameters"]):
        assert res.pui.box[k].lo == p["lower"] and res.pui.box[k].hi == p["upper"]
        assert res.pui.central[k] == p["central"]
        assert res.pui.box[k].contains(theta[k])  # and the guarantee holds on this data


def test_ss_uncertainty_equals_the_app(tmp_path, app):
    rng = np.random.default_rng(12)
    sys_ = sets.examples.farah_system()
    N = 400
    u = np.sign(rng.uniform(-1, 1, (N, 2)))
    y = sets.simulate_state_space(sys_, u)
    y += 0.05 * rng.normal(size=y.shape)
    write_csv(tmp_path / "ss.csv", {"u1": u[:, 0], "u2": u[:, 1], "y1": y[:, 0], "y2": y[:, 1]})
    app("sets-ss-uncertainty", "--data", tmp_path / "ss.csv", "--inputs", "u1,u2", "--outputs", "y1,y2", "--order", 3,
        "--past", 10, "--json", tmp_path / "ss.json")
    expected = json.loads((tmp_path / "ss.json").read_text())
    opts = sets.SsUncertaintyOptions(identification=sets.PropagatorOptions(order=3, past=10))
    res = sets.ss_uncertainty(u, y, opts)
    names = res.identification.structure.parameter_names
    assert names == [p["name"] for p in expected["parameters"]]
    box = sets.outer_box(res.estimate_level_set.ellipsoid)
    pui = res.estimate_fps_pui
    assert res.estimate_level_set.ell == expected["ell"]
    assert pui.guaranteed == expected["pui_guaranteed"]
    for k, p in enumerate(expected["parameters"]):
        assert res.identification.theta[k] == p["estimate"]
        assert [box[k].lo, box[k].hi] == p["ellipsoid_box"]
        assert [pui.box[k].lo, pui.box[k].hi] == p["pui"]


def test_hinf_bound_equals_the_app(tmp_path, app):
    rng = np.random.default_rng(13)
    G = sets.examples.hakvoort_system()
    N = 1000
    u = rng.uniform(-1, 1, N + 500)
    # y = G u (lfilter with the model's b, a), then coloured noise; the first 500 samples are dropped
    y = np.zeros_like(u)
    b, a = G.b, G.a
    for t in range(len(u)):
        acc = sum(b[k] * u[t - k] for k in range(len(b)) if t - k >= 0)
        acc -= sum(a[k] * y[t - k] for k in range(1, len(a)) if t - k >= 0)
        y[t] = acc
    u, y = u[500:], y[500:] + 0.005 * rng.normal(size=N)
    write_csv(tmp_path / "h.csv", {"u": u, "y": y})
    M = 2.0
    app("sets-hinf-bound", "--data", tmp_path / "h.csv", "--u", "u", "--y", "y", "--M", M, "--M-ic", 1.0,
        "--rho-ic", 0.975, "--order", 20,
        "--grid", 40, "--quiet", "--json", tmp_path / "h.json")
    expected = json.loads((tmp_path / "h.json").read_text())
    grid = np.pi * (np.arange(40) + 0.5) / 40
    basis = sets.OrthonormalBasis.kautz(0.93 * np.exp(0.66j))
    priors = sets.HinfPriors(M=M, rho=0.88, u_bar=1.0, M_ic=1.0, rho_ic=0.975)
    structure = sets.HinfStructure(basis=basis, order=20, priors=priors, grid=sets.midpoint_grid(40))
    np.testing.assert_array_equal(structure.grid, grid)
    res = sets.hinf_bound(sets.HinfData(u=u, y=y), structure)  # the entry point the app calls
    old = sets.hinf_bound(u, y, basis, 20, grid, priors)  # and the long form gives the same
    assert old.bound.b == res.bound.b
    assert res.bound.b == expected["b"]
    assert res.bound.b_grid == expected["b_grid"]
    np.testing.assert_array_equal(res.set.frequencies, expected["frequencies"])
    np.testing.assert_array_equal(res.delta, expected["delta"])
    # stochastic noise (the default): consistency is not asked, so neither empty nor falsified
    assert res.set.consistency.falsified == sets.Falsified.unknown
    assert not res.set.empty and res.set.falsification == ""
