"""Set types through the bindings keep their guarantees: sample the true set, apply the
operation to every sample, check each image lies in the computed outer approximation (by a
proven membership or a rigorous support bound). Bad input raises the named exception."""

import numpy as np
import pytest

import sets

RNG_SEED = 20240516


def random_zonotope(rng, n, m):
    return sets.Zonotope(rng.normal(size=n), rng.normal(size=(n, m)))


def zonotope_samples(Z, rng, k=400):
    xi = rng.uniform(-1, 1, size=(Z.num_generators, k))
    xi[:, : k // 4] = np.sign(xi[:, : k // 4])  # vertices too
    return (Z.center[:, None] + Z.generators @ xi).T


def directions(rng, n, k=40):
    d = rng.normal(size=(k, n))
    return d / np.linalg.norm(d, axis=1)[:, None]


def assert_inside_support(S, points, dirs):
    """Every point's projection on every direction is below the set's rigorous support bound."""
    for d in dirs:
        h = sets.support(S, d)
        assert np.max(points @ d) <= h, "a sampled image lies outside the outer approximation"


def test_zonotope_linear_map_and_sum_contain_every_image():
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(20):
        n = int(rng.integers(2, 5))
        Z1, Z2 = random_zonotope(rng, n, int(rng.integers(1, 7))), random_zonotope(rng, n, int(rng.integers(1, 7)))
        A = rng.normal(size=(n, n))
        x1, x2 = zonotope_samples(Z1, rng), zonotope_samples(Z2, rng)
        image = x1 @ A.T
        AZ = sets.linear_map(A, Z1)
        assert_inside_support(AZ, image, directions(rng, n))
        S = sets.minkowski_sum(Z1, Z2)
        assert_inside_support(S, x1 + x2, directions(rng, n))
        box = sets.outer_box(AZ)
        assert all(box.contains(p) for p in image)


@pytest.mark.parametrize("method", [sets.ReductionMethod.girard, sets.ReductionMethod.combastel, sets.ReductionMethod.pca])
def test_reduce_order_contains_the_zonotope(method):
    rng = np.random.default_rng(RNG_SEED + 1)
    for _ in range(10):
        n = int(rng.integers(2, 4))
        Z = random_zonotope(rng, n, 12)
        R = sets.reduce_order(Z, 2, method)
        assert R.num_generators <= 2 * n
        pts = zonotope_samples(Z, rng)
        assert_inside_support(R, pts, directions(rng, n))
        # proven membership where the LP can decide: never a proven "no" for a point of Z
        for p in pts[:40]:
            assert sets.contains(R, p) != sets.BoolInterval.no


def test_ellipsoid_operations_contain_every_image():
    rng = np.random.default_rng(RNG_SEED + 2)
    for _ in range(20):
        n = 3
        L = rng.normal(size=(n, n))
        E = sets.Ellipsoid(rng.normal(size=n), L @ L.T + 0.1 * np.eye(n))
        # points of E: c + P^(1/2) u, |u| <= 1
        w, V = np.linalg.eigh(E.shape)
        root = V @ np.diag(np.sqrt(np.maximum(w, 0))) @ V.T
        u = rng.normal(size=(300, n))
        u *= (rng.uniform(size=(300, 1)) ** (1 / n)) / np.linalg.norm(u, axis=1)[:, None] * 0.999999
        pts = E.center + u @ root.T
        A = rng.normal(size=(2, n))
        assert_inside_support(sets.linear_map(A, E), pts @ A.T, directions(rng, 2))
        F = sets.Ellipsoid.ball(np.zeros(n), 0.5)
        assert_inside_support(sets.minkowski_sum(E, F), pts + 0.5 * u[::-1], directions(rng, n))
        a = rng.normal(size=n)
        y = float(a @ E.center)
        inside = pts[np.abs(y - pts @ a) <= 0.3]
        if len(inside):
            assert_inside_support(sets.intersect_strip(E, a, y, 0.3), inside, directions(rng, n))


def test_hpolytope_of_a_zonotope_contains_it_and_vertices_round_trip():
    rng = np.random.default_rng(RNG_SEED + 3)
    Z = random_zonotope(rng, 2, 5)
    H = sets.to_hpolytope(Z)
    pts = zonotope_samples(Z, rng)
    assert np.all(pts @ H.A.T <= H.b + 1e-9 * (1 + np.abs(H.b)))
    V = sets.to_vpolytope(Z)
    assert V.num_points == 10  # 2 m vertices of a 2-D zonotope with 5 generators in general position
    assert_inside_support(H, V.points.T, directions(rng, 2))


def test_projection_polygon_contains_projected_samples():
    rng = np.random.default_rng(RNG_SEED + 4)
    Z = random_zonotope(rng, 4, 6)
    poly = sets.projection_polygon(Z, 1, 3)
    pts = zonotope_samples(Z, rng)[:, [1, 3]]
    # counter-clockwise polygon: every point is left of every edge (up to rounding)
    v = np.asarray(poly).T
    for k in range(len(v)):
        a, b = v[k], v[(k + 1) % len(v)]
        cross = (b[0] - a[0]) * (pts[:, 1] - a[1]) - (b[1] - a[1]) * (pts[:, 0] - a[0])
        assert np.all(cross >= -1e-9 * np.linalg.norm(b - a) * (1 + np.abs(pts).max()))


def test_set_json_round_trip_is_exact():
    rng = np.random.default_rng(RNG_SEED + 5)
    for s in [random_zonotope(rng, 3, 4), sets.Ellipsoid(np.zeros(2), np.eye(2) * 0.3),
              sets.HPolytope(np.eye(2), np.array([1.0, np.inf])), sets.VPolytope(rng.normal(size=(2, 5))),
              sets.Box(np.array([0.1, 0.2]), np.array([0.3, 0.4]))]:
        back = sets.set_from_json(sets.set_to_json(s))
        assert type(back) is type(s)
        assert sets.set_to_string(back) == sets.set_to_string(s)


def test_bad_input_raises_named_exceptions():
    with pytest.raises(sets.InputError):
        sets.Zonotope(np.zeros(2), np.zeros((3, 1)))
    with pytest.raises(sets.InputError):
        sets.Ellipsoid(np.zeros(2), np.array([[1.0, 0.0], [0.0, -1.0]]))  # indefinite
    with pytest.raises(sets.UnsupportedError):
        sets.to_vpolytope(sets.to_hpolytope(sets.Box(np.zeros(4), np.ones(4))))  # H->V above 3-D
    with pytest.raises(sets.EmptySetError):
        sets.outer_box(sets.HPolytope(np.array([[1.0], [-1.0]]), np.array([0.0, -1.0])))  # x <= 0, x >= 1
    with pytest.raises(sets.EmptySetError):
        sets.intersect_strip(sets.Ellipsoid.ball(np.zeros(2), 1.0), np.array([1.0, 0.0]), 5.0, 0.1)
    with pytest.raises(sets.InputError, match="shape"):
        sets.set_from_json({"type": "ellipsoid", "center": [0, 0]})
    with pytest.raises(NotImplementedError):  # UnsupportedError is also a NotImplementedError
        sets.to_vpolytope(sets.to_hpolytope(sets.Box(np.zeros(4), np.ones(4))))
