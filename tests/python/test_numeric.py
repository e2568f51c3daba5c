"""Interval and Box: outward rounding, bad input, pickling."""

import fractions
import pickle

import numpy as np
import pytest

import sets


def test_one_third_is_enclosed_and_not_degenerate():
    x = sets.Interval(1.0) / sets.Interval(3.0)
    third = fractions.Fraction(1, 3)
    assert fractions.Fraction(x.lo) <= third <= fractions.Fraction(x.hi)
    assert x.lo < x.hi  # the exact quotient is not a double: both ends cannot coincide


def test_decimal_from_string_encloses_the_real_number():
    x = sets.Interval.from_string("0.1")
    tenth = fractions.Fraction(1, 10)
    assert fractions.Fraction(x.lo) <= tenth <= fractions.Fraction(x.hi)
    assert x.lo < x.hi


def test_random_sums_and_products_enclose_exact_rationals():
    rng = np.random.default_rng(1)
    for _ in range(300):
        a, b, c = rng.normal(size=3) * 10.0 ** rng.integers(-5, 5, size=3)
        x = (sets.Interval(a) + sets.Interval(b)) * sets.Interval(c) - sets.Interval(a) / sets.Interval(c)
        exact = (fractions.Fraction(a) + fractions.Fraction(b)) * fractions.Fraction(c) - fractions.Fraction(a) / fractions.Fraction(c)
        assert fractions.Fraction(x.lo) <= exact <= fractions.Fraction(x.hi)


def test_python_floats_are_left_in_round_to_nearest():
    sets.Interval(1.0) / sets.Interval(3.0)
    assert 1.0 / 3.0 == 0.3333333333333333  # the FPU mode is restored after the call


def test_bad_interval_raises_input_error():
    with pytest.raises(sets.InputError):
        sets.Interval(2.0, 1.0)
    with pytest.raises(ValueError):  # InputError is also a ValueError
        sets.Interval(float("nan"), 1.0)


def test_box_accessors_and_bad_input():
    b = sets.Box(np.array([0.0, -1.0]), np.array([1.0, 2.5]))
    assert b.dimension == 2 and len(b) == 2
    np.testing.assert_array_equal(b.lower, [0.0, -1.0])
    np.testing.assert_array_equal(b.upper, [1.0, 2.5])
    assert b[1].hi == 2.5 and b[-1].lo == -1.0
    assert b.contains(np.array([0.5, 2.5])) and not b.contains(np.array([1.5, 0.0]))
    assert b.volume() >= 3.5
    np.testing.assert_array_equal(b.to_array(), [[0.0, 1.0], [-1.0, 2.5]])
    with pytest.raises(sets.InputError):
        sets.Box(np.array([1.0]), np.array([0.0]))
    with pytest.raises(sets.InputError, match="entries"):
        b.contains(np.array([1.0, 2.0, 3.0]))


def test_pickle_round_trip():
    b = sets.Box(np.array([0.1, -1.0]), np.array([1.0, np.inf]))
    assert pickle.loads(pickle.dumps(b)) == b
    x = sets.Interval.from_string("0.1")
    assert pickle.loads(pickle.dumps(x)) == x


def test_bool_interval_unknown_has_no_truth_value():
    assert bool(sets.BoolInterval.yes) and not bool(sets.BoolInterval.no)
    with pytest.raises(ValueError):
        bool(sets.BoolInterval.unknown)
