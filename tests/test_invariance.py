"""Identified properties do not depend on the frame or the units of the test."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from massline.core import Lines, Masslines, identify, synthesise
from massline.placement.hand_layouts import structure_exciters, structure_sensors

vectors = st.tuples(*[st.floats(-1.0, 1.0, allow_nan=False)] * 3).map(np.array)
METHODS = st.sampled_from([("method2", "method3"), ("method2-difference", "method3"), ("method2", "method2")])


def _close(a, b, scale_len, rtol=1e-8):
    assert abs(a.mass - b.mass) <= rtol * b.mass
    np.testing.assert_allclose(a.cog, b.cog, atol=rtol * scale_len)
    np.testing.assert_allclose(a.inertia_cog, b.inertia_cog, atol=rtol * np.abs(b.inertia_cog).max())


@settings(max_examples=60, deadline=None)
@given(rotvec=vectors, translation=vectors, methods=METHODS)
def test_identification_is_invariant_under_a_change_of_frame(structure, rotvec, translation, methods):
    """Identify in frame O and in frame O' (x' = R x + t): the same body, moved."""
    R = Rotation.from_rotvec(3 * rotvec).as_matrix()
    sensors, exciters = structure_sensors(), structure_exciters(2)[:4]
    here = identify(synthesise(structure, sensors, exciters), *methods).body
    there = identify(synthesise(structure, sensors, exciters).transformed(R, translation), *methods).body
    _close(there, here.transformed(R, translation), structure.radius_of_gyration)
    np.testing.assert_allclose(there.principal_moments, here.principal_moments, rtol=1e-8)


@settings(max_examples=40, deadline=None)
@given(length=st.sampled_from([1e-3, 0.0254, 1.0, 1000.0, 1 / 0.0254]), mass=st.sampled_from([1.0, 0.45359237, 1e3]))
def test_identification_is_invariant_under_a_change_of_units(structure, length, mass):
    """Lengths × L and masses × M in, the same body (in those units) out."""
    sensors, exciters = structure_sensors(), structure_exciters()
    reference = identify(synthesise(structure, sensors, exciters)).body
    scaled_body = structure.scaled(length, mass)
    found = identify(synthesise(scaled_body, sensors.scaled(length), exciters.scaled(length))).body
    _close(found.scaled(1 / length, 1 / mass), reference, structure.radius_of_gyration)


@settings(max_examples=30, deadline=None)
@given(sign=st.sampled_from([-1.0, 1.0]), which=st.integers(0, 5))
def test_a_reversed_sensor_is_the_same_measurement(structure, sign, which):
    """Reversing a sensor's direction negates its masslines: nothing identified changes."""
    sensors, exciters = structure_sensors(), structure_exciters()
    data = synthesise(structure, sensors, exciters)
    directions = sensors.directions.copy()
    directions[which] *= sign
    values = data.values.copy()
    values[which] *= sign
    flipped = Masslines(values, Lines(sensors.points, directions), exciters)
    _close(identify(flipped).body, structure, structure.radius_of_gyration)
