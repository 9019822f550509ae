"""The paper's singular layouts are refused with the reason, never solved."""

import numpy as np
import pytest

from massline.core import Lines, SingularLayoutError, identify, synthesise
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.core.kinematics import method2_difference


def test_triaxial_at_one_point_for_kinematics_method1(structure):
    """§2.1.1: a single transduction point in three directions makes eq. (5) singular."""
    sensors = Lines.along_axes(np.zeros((3, 3)), [0, 1, 2]) + Lines.triaxials([[0.16, 0.12, 0.006]])
    data = synthesise(structure, sensors, structure_exciters())
    with pytest.raises(SingularLayoutError, match=r"eq\. \(5\).*one point.*at most two directions"):
        identify(data, "method1", "method3")


def test_two_triaxial_points_leave_rotation_about_their_line_unseen(structure):
    p1, p2 = np.array([0.16, 0.0, 0.012]), np.array([0.0, 0.12, 0.15])
    data = synthesise(structure, Lines.triaxials([p1, p2]), structure_exciters())
    with pytest.raises(SingularLayoutError, match="rank 5 of 6") as err:
        identify(data)
    message = str(err.value)
    assert "two points" in message and "rotation about the line" in message
    # the unseen axis named in the message is the line joining the two points
    u = (p2 - p1) / np.linalg.norm(p2 - p1)
    axis = np.array([float(x.replace("−", "-")) for x in message.split("along (")[1].split(")")[0].split(",")])
    assert abs(abs(axis @ u) - 1) < 1e-3


def test_all_sensors_parallel(structure):
    rng = np.random.default_rng(1)
    sensors = Lines(rng.uniform(0, 0.1, (8, 3)), np.tile([0.0, 0.0, 1.0], (8, 1)))
    with pytest.raises(SingularLayoutError, match="parallel to"):
        identify(synthesise(structure, sensors, structure_exciters()))


def test_too_few_sensors(structure):
    with pytest.raises(SingularLayoutError, match="at least 6"):
        identify(synthesise(structure, structure_sensors()[:5], structure_exciters()))


def test_all_exciters_parallel(structure):
    exciters = Lines.along_axes([[0.13, 0.10, 0.0], [0.03, 0.02, 0.0], [0.15, 0.01, 0.0]], [2, 2, 2])
    with pytest.raises(SingularLayoutError, match="all 3 exciters are parallel"):
        identify(synthesise(structure, structure_sensors(), exciters))


def test_coincident_coordinates_in_the_kinematic_difference_system(structure):
    """Eq. (7): two x-sensors whose y and z coincide give a zero row."""
    reference = structure_sensors()
    points = reference.points.copy()
    points[1] = [0.0, *points[0][1:]]  # the second x-sensor moved along x only
    sensors = Lines(points, reference.directions)
    data = synthesise(structure, sensors, structure_exciters())
    with pytest.raises(SingularLayoutError, match="sensors 0 .* and 1 .* coincident coordinates"):
        method2_difference(data)


def test_coincident_coordinates_in_the_dynamic_difference_system(structure):
    """The 9×6 system under eq. (8): two x-hits differing only in x."""
    exciters = structure_exciters(2)
    points = exciters.points.copy()
    points[3] = points[0] + [0.05, 0.0, 0.0]
    data = synthesise(structure, structure_sensors(), Lines(points, exciters.directions))
    with pytest.raises(SingularLayoutError, match="exciters 0 .* and 3 .* coincident coordinates"):
        identify(data, "method2", "method1")


def test_a_singular_layout_is_caught_even_when_nearly_so(structure):
    """A layout singular to rounding is refused, not solved to garbage."""
    p1, p2 = np.array([0.16, 0.0, 0.012]), np.array([0.0, 0.12, 0.15])
    sensors = Lines.triaxials([p1, p2]) + Lines([(p1 + p2) / 2], [[0.0, 0.0, 1.0]])  # on the joining line
    with pytest.raises(SingularLayoutError):
        identify(synthesise(structure, sensors, structure_exciters()))
