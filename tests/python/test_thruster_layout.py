"""Thruster layout (guidance/thruster_layout.hpp through satgnc.guidance.thrusters): allocation, the
input matrix, survivors and the setup errors (messages asserted)."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc.guidance import cw_matrices
from satgnc.guidance.thrusters import ThrusterLayout, axis_layout, cube_layout, impulse_bit_violations


def test_axis_layout_allocation_and_input_matrix():
    lay = axis_layout(2.0)
    assert lay.size == 6
    assert lay.names == ("+x", "-x", "+y", "-y", "+z", "-z")
    D = lay.allocation()
    # exact: unit axes stored as given
    want = np.array([[1, -1, 0, 0, 0, 0], [0, 0, 1, -1, 0, 0], [0, 0, 0, 0, 1, -1]])
    np.testing.assert_array_equal(D, want)
    _, B = cw_matrices(1.1e-3, 50.0)
    Bt = lay.input_matrix(B)
    # B D column by column, to round-off (entries 1/50)
    np.testing.assert_allclose(Bt, B @ D, rtol=0, atol=1e-17)
    np.testing.assert_array_equal(lay.max_thrust, np.full(6, 2.0))
    np.testing.assert_array_equal(lay.min_impulse_bit, np.zeros(6))


def test_cube_layout_twelve_thrusters_span_and_torque():
    lay = cube_layout(1.0, cant_deg=30.0)
    assert lay.size == 12
    D = lay.allocation()
    # unit directions to round-off (cos^2 + sin^2)
    np.testing.assert_allclose(np.linalg.norm(D, axis=0), 1.0, rtol=0, atol=1e-15)
    assert np.linalg.matrix_rank(D) == 3
    # the pair on one face cancels its cant: +xa + +xb = 2 cos(30 deg) e_x (round-off)
    np.testing.assert_allclose(D[:, 0] + D[:, 1], [2 * np.cos(np.radians(30)), 0, 0], atol=1e-15)
    # torque r x d of thruster 0: r = (-0.5, -0.25, 0), d = (cos, sin, 0) -> z = -0.5 sin + 0.25 cos
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    np.testing.assert_allclose(lay.torque_allocation()[:, 0], [0, 0, -0.5 * s + 0.25 * c], atol=1e-15)


def test_survivors_without_and_forces():
    lay = axis_layout(1.0)
    assert lay.survivors([4, 1]) == [0, 2, 3, 5]
    s = lay.without([4, 1])
    assert s.names == ("+x", "+y", "-y", "-z")
    F = s.forces(np.array([[1.0, 0.0, 0.5, 2.0]]))
    np.testing.assert_array_equal(F, [[1.0, -0.5, -2.0]])  # exact sums of unit axes


def test_impulse_bit_violations_counts_short_firings():
    lay = ThrusterLayout(np.eye(3), np.ones(3), min_impulse_bit=[0.1, 0.1, 0.0])
    T = np.array([[0.01, 0.5, 0.0], [0.0, 0.0, 1e-3]])  # impulses at dt = 2 s: 0.02 (< 0.1), 1.0, 2e-3
    assert impulse_bit_violations(lay, T, 2.0) == 1


@pytest.mark.parametrize(
    "kw, err, msg",
    [
        (dict(directions=[[1.0, 1.0, 0.0]], max_thrust=[1.0]), ValueError,
         "thrusters[0].direction: must be a unit vector, got norm 1.4142135623730951 (hint: divide the "
         "direction by its norm; tolerance 1e-9)"),
        (dict(directions=[[1.0, 0, 0], [0, 1.0, 0]], max_thrust=[1.0, -2.0]), ValueError,
         "thrusters[1].max_thrust: must be finite and > 0 N, got -2"),
        (dict(directions=[[1.0, 0, 0]], max_thrust=[1.0], min_impulse_bit=[-1e-3]), ValueError,
         "thrusters[0].min_impulse_bit: must be finite and >= 0 N s, got -0.001"),
        (dict(directions=[[1.0, 0, 0]], max_thrust=[1.0, 2.0]), ValueError,
         "max_thrust: must have shape (1,), got (2,)"),
        (dict(directions=[[1.0, 0]], max_thrust=[1.0]), ValueError,
         "directions: must have shape (n, 3), got (1, 2)"),
        (dict(directions=[[1.0, 0, 0], [0, 1.0, 0]], max_thrust=[1.0, 1.0], names=("a", "a")), ValueError,
         "thrusters[1].name: must be unique, 'a' repeats"),
        (dict(directions=[[1.0, 0, 0]], max_thrust=[1.0], names="a"), TypeError,
         "names: must be a list of strings, got str"),
        (dict(directions=np.zeros((0, 3)), max_thrust=np.zeros(0)), ValueError,
         "directions: must hold at least one thruster (shape (m, 3), m >= 1)"),
    ],
)
def test_bad_layouts_name_the_thruster_and_rule(kw, err, msg):
    with pytest.raises(err) as e:
        ThrusterLayout(**kw)
    assert str(e.value) == msg


def test_bad_failures_and_table_rows():
    lay = axis_layout(1.0)
    with pytest.raises(ValueError) as e:
        lay.survivors([7])
    assert str(e.value) == "failed[0]: must be a thruster index in [0, 6), got 7"
    with pytest.raises(TypeError) as e:
        lay.survivors([1.5])
    assert str(e.value) == "failed[0]: must be an integer thruster index, got float"
    with pytest.raises(ValueError) as e:
        ThrusterLayout.from_table([{"direction": [1, 0, 0], "max_thrust": 1.0, "thrust": 2.0}])
    assert str(e.value) == "rows[0]: unknown key 'thrust'; known: ['direction', 'max_thrust', " \
                           "'min_impulse_bit', 'name', 'position']"
    t = ThrusterLayout.from_table([{"direction": [0, 0, -1], "max_thrust": 0.5, "name": "down",
                                    "min_impulse_bit": 1e-3, "position": [0, 0, 0.4]}])
    assert t.names == ("down",) and t.min_impulse_bit[0] == 1e-3 and t.positions[0, 2] == 0.4


def test_thrust_bounds_are_exact_and_lower_relaxation_is_deprecated():
    from satgnc.guidance import thrusters

    lay = thrusters.axis_layout(0.2)
    lo, hi = thrusters.thrust_bounds(lay)
    # the solver handles a bound at the L1 kink: the lower bound is exactly 0 (no -1e-12 relaxation)
    assert lo.shape == hi.shape == (lay.size,) and np.all(lo == 0.0) and np.array_equal(hi, lay.max_thrust)
    with pytest.warns(DeprecationWarning, match="LOWER_RELAXATION is deprecated; use thrust_bounds"):
        assert thrusters.LOWER_RELAXATION == 1e-12  # the old value, still importable
    assert "LOWER_RELAXATION" not in thrusters.__all__
