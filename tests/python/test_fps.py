"""Feasible parameter sets through the bindings: PUIs contain every sampled feasible parameter
(and the true one), the guarantee flag, the falsification report, bad input."""

import numpy as np
import pytest

import sets


def strip_data(rng, N=60, p=2, delta=0.1):
    theta = rng.normal(size=p)
    Phi = rng.normal(size=(N, p))
    y = Phi @ theta + rng.uniform(-delta, delta, size=N)
    return theta, Phi, y, np.full(N, delta)


def rejection_samples(Phi, y, delta, box, rng, k=20000):
    lo, hi = box.lower, box.upper
    th = lo + (hi - lo) * rng.uniform(size=(k, len(lo)))
    ok = np.all(np.abs(y[None, :] - th @ Phi.T) <= delta[None, :] * (1 - 1e-9), axis=1)
    return th[ok]


def test_pui_contains_the_truth_and_every_feasible_sample():
    rng = np.random.default_rng(7)
    for _ in range(10):
        theta, Phi, y, delta = strip_data(rng)
        fps = sets.FeasibleParameterSet.from_data(Phi, y, delta)
        r = sets.pui(fps)
        assert not r.empty and r.guaranteed
        assert r.box.contains(theta)
        wide = sets.Box(r.box.lower - 0.5 * (r.box.upper - r.box.lower), r.box.upper + 0.5 * (r.box.upper - r.box.lower))
        pts = rejection_samples(Phi, y, delta, wide, rng)
        assert len(pts) > 10
        assert all(r.box.contains(p) for p in pts)
        assert fps.contains(theta) != sets.BoolInterval.no
        # support in a few directions bounds every sample
        dirs = [np.array([1.0, 1.0]), np.array([1.0, -2.0]), np.array([-0.3, 1.0])]
        s = sets.support(fps, dirs)
        assert s.guaranteed
        for d, h in zip(dirs, s.maxima):
            assert np.max(pts @ d) <= h


def test_outer_zonotope_contains_every_feasible_sample():
    rng = np.random.default_rng(8)
    theta, Phi, y, delta = strip_data(rng, N=40, p=3)
    fps = sets.FeasibleParameterSet.from_data(Phi, y, delta)
    Z = sets.outer_zonotope(fps, sets.FpsZonotopeOptions(max_order=5))
    r = sets.pui(fps)
    pts = rejection_samples(Phi, y, delta, r.box, rng, k=100000)
    assert len(pts) > 5
    for d in rng.normal(size=(30, 3)):
        assert np.max(np.r_[pts, theta[None, :]] @ d) <= sets.support(Z, d)


def test_errors_in_variables_pui_contains_the_truth():
    rng = np.random.default_rng(9)
    N, p, dphi, dy = 50, 2, 0.05, 0.05
    theta = np.array([0.7, -0.4])
    Phi = rng.normal(size=(N, p))
    y = Phi @ theta + rng.uniform(-dy, dy, size=N)
    Phi_meas = Phi + rng.uniform(-dphi, dphi, size=(N, p))
    fps = sets.FeasibleParameterSet.from_interval_data(Phi_meas - dphi, Phi_meas + dphi, y - dy, y + dy)
    assert fps.has_interval_regressors and len(fps) == N
    r = sets.pui(fps, sets.PuiOptions(orthants=sets.OrthantSelection.all))
    assert r.guaranteed and r.box.contains(theta)
    assert len(r.orthants) == 4


def test_contradictory_data_give_a_falsification_report():
    # theta = 1 and theta = 3 +- 0.5: no parameter satisfies both samples
    fps = sets.FeasibleParameterSet.from_data(np.array([[1.0], [1.0], [1.0]]), np.array([1.0, 1.1, 3.0]),
                                              np.array([0.5, 0.5, 0.5]))
    r = sets.pui(fps)
    assert r.empty
    assert 2 in r.falsification.samples
    assert "sample" in r.falsification.message()
    with pytest.raises(sets.EmptySetError):
        sets.outer_zonotope(fps, sets.FpsZonotopeOptions(initial=sets.Zonotope(np.zeros(1), np.eye(1) * 10)))


def test_bad_fps_input_raises_input_error():
    with pytest.raises(sets.InputError):
        sets.FeasibleParameterSet.from_data(np.ones((3, 2)), np.ones(4), np.ones(3))
    with pytest.raises(sets.InputError):
        sets.FeasibleParameterSet.from_data(np.ones((3, 2)), np.ones(3), -np.ones(3))
    with pytest.raises(sets.InputError, match="lower > upper"):
        sets.FeasibleParameterSet.from_interval_data(np.ones((2, 2)), np.zeros((2, 2)), np.zeros(2), np.ones(2))
    fps = sets.FeasibleParameterSet(2)
    with pytest.raises(sets.InputError):
        fps.contains(np.zeros(3))
    with pytest.raises(AttributeError):
        sets.PropagatorOptions(no_such_field=1)
