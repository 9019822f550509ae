"""Hand layouts like the paper's, on the bundled bodies (tests, demo, baselines).

Points are on the bodies' surfaces (meshes/generate.py gives the boxes) and
every direction is a coordinate axis, as a technician would lay them out.
"""

from __future__ import annotations

import numpy as np

from massline.core.lines import Lines


def plate_table1() -> tuple[Lines, Lines]:
    """Four sensors and three exciters, all along z, on the Table 1 plate."""
    sensors = Lines.along_axes(
        [[-0.06, -0.08, 0.0025], [0.06, -0.08, 0.0025], [0.06, 0.20, 0.0025], [-0.06, 0.20, 0.0025]], [2, 2, 2, 2]
    )
    exciters = Lines.along_axes([[0.0, -0.07, 0.0025], [-0.05, 0.15, 0.0025], [0.05, 0.12, 0.0025]], [2, 2, 2])
    return sensors, exciters


def structure_sensors() -> Lines:
    """Six uniaxial sensors, two along each axis, for eq. (6)."""
    points = [
        [0.16, 0.06, 0.006],
        [0.012, 0.10, 0.13],  # x: base end, upright face
        [0.10, 0.12, 0.006],
        [0.006, 0.0, 0.12],  # y: base side, upright side
        [0.15, 0.01, 0.012],
        [0.11, 0.11, 0.012],  # z: base top, two corners
    ]
    return Lines.along_axes(points, [0, 0, 1, 1, 2, 2])


def structure_exciters(sets: int = 1) -> Lines:
    """Hammer hits along x, y, z (``sets`` = 2 doubles them for dynamics method 1)."""
    first = Lines.along_axes([[0.0, 0.09, 0.10], [0.12, 0.0, 0.006], [0.13, 0.10, 0.0]], [0, 1, 2])
    second = Lines.along_axes([[0.0, 0.03, 0.05], [0.006, 0.12, 0.10], [0.03, 0.02, 0.0]], [0, 1, 2])
    return first if sets == 1 else first + second


def structure_origin_sensors() -> Lines:
    """Eq. (5): the origin corner along x, y, z plus three transduction lines at two points."""
    origin = Lines.along_axes(np.zeros((3, 3)), [0, 1, 2])
    others = Lines.along_axes([[0.16, 0.12, 0.006], [0.16, 0.12, 0.006], [0.006, 0.06, 0.15]], [1, 2, 0])
    return origin + others


def bracket_sensors() -> Lines:
    """Six uniaxial sensors on the bracket, along the frame axes, two per axis."""
    return Lines.along_axes(
        [[0.1, 0.0, 0.0], [0.0, 0.07, 0.06], [0.06, 0.0, 0.01], [0.0, 0.07, 0.0], [0.12, 0.07, 0.01], [0.0, 0.0, 0.06]],
        [0, 0, 1, 1, 2, 2],
    )


def bracket_exciters() -> Lines:
    """Six hits on the bracket (the first three along x, y, z: the minimal set)."""
    return Lines.along_axes(
        [
            [0.0, 0.03, 0.03],
            [0.08, 0.0, 0.005],
            [0.09, 0.05, 0.0],
            [0.0, 0.06, 0.05],
            [0.03, 0.07, 0.005],
            [0.02, 0.01, 0.01],
        ],
        [0, 1, 2, 0, 1, 2],
    )
