"""The test's point labels: the numbers a test engineer writes beside each accelerometer and hit.

One numbering from the plan to the reports: the plan prints and stores these labels, the simulated Universal
File writes them as its node labels, and identify and diagnose name channels by them. A *point* is one
accelerometer (a triaxial's three lines, or the mutually orthogonal uniaxial lines glued at one spot: one node
of a Universal File, with up to three direction codes) or one hit spot. Accelerometers are numbered from 1 in
the order of their first line; hits from the next hundred (101, … after up to 99 accelerometers; 201, … after
up to 199), also where a hit sits on an accelerometer's point.
"""

from __future__ import annotations

import numpy as np

from massline.core.lines import Lines

POINT_TOL = 1e-9  # m: lines closer than this share a point
ORTHOGONALITY_TOL = 1e-9  # |dᵢ · dⱼ| below which two lines at one point are channels of one accelerometer


def point_groups(lines: Lines) -> np.ndarray:
    """The point (0, 1, …, in order of first line) of each line (n,).

    A triaxial accelerometer's lines are one point; a uniaxial line joins the first earlier uniaxial point at
    the same place whose lines it is orthogonal to, while that point has fewer than three lines; else it starts
    a point of its own.
    """
    group = np.full(len(lines), -1)
    members: list[list[int]] = []
    triaxial: dict[int, int] = {}
    for i, (p, d, t) in enumerate(zip(lines.points, lines.directions, lines.triaxial)):
        if t >= 0:
            group[i] = triaxial.setdefault(int(t), len(members))
            if group[i] == len(members):
                members.append([])
        else:
            group[i] = next((g for g, m in enumerate(members) if _joins(lines, m, p, d)), len(members))
            if group[i] == len(members):
                members.append([])
        members[group[i]].append(i)
    return group


def _joins(lines: Lines, member: list[int], point: np.ndarray, direction: np.ndarray) -> bool:
    """May a uniaxial line at ``point`` along ``direction`` join the point of lines ``member``?"""
    return (
        0 < len(member) < 3
        and bool(np.all(lines.triaxial[member] < 0))
        and float(np.abs(lines.points[member] - point).max()) <= POINT_TOL
        and float(np.abs(lines.directions[member] @ direction).max()) <= ORTHOGONALITY_TOL
    )


def first_hit_label(n_accelerometers: int) -> int:
    """The label of the first hit: the hundred after the accelerometers' labels, plus one."""
    return 100 * (n_accelerometers // 100 + 1) + 1


def point_labels(sensors: Lines, exciters: Lines) -> tuple[np.ndarray, np.ndarray]:
    """The label of every sensor line (n_s,) and of every exciter line (n_e,): accelerometers from 1, hits from
    :func:`first_hit_label`."""
    s_group, e_group = point_groups(sensors), point_groups(exciters)
    n_accelerometers = int(s_group.max(initial=-1)) + 1
    return s_group + 1, e_group + first_hit_label(n_accelerometers)
