"""Where each line goes in a Universal File: nodes, their displacement frames, direction codes.

A node is one of the test's points, labelled as the plan labels it (:mod:`massline.core.numbering`: accelerometers
from 1, hits from the next hundred): a triaxial accelerometer, or orthogonal uniaxial lines at one spot, is one node
with codes 1, 2, 3 along its channels (a left-handed triad has its third axis flipped and code -3); a lone uniaxial
line gets the frame nearest to the identity whose axis k (the global axis closest to the line) lies along ±d, so
that a slightly tilted "+z" sensor is still code +3. Lines along ± global axes keep the global frame. A code c at a node of frame R is the
global direction sign(c) R[:, |c| - 1] (`line_from_code`).

The setup a technician loads into test software (:func:`setup_layout`) is laid out as Test.Lab exports geometry:
every node has a coordinate system of its own, numbered like it, at its point; a lone line is that system's +Z
(the accelerometer's axis, the hammer's swing), an accelerometer of two or three channels has them along its x, y, z.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import AXES, Lines, skew
from massline.core.numbering import POINT_TOL, point_groups, point_labels
from massline.uff.recording import code_direction

AXIS_TOL = 1e-12  # a unit direction is along a global axis when it is this close to it
SAME_DIRECTION_TOL = 1e-9  # two unit directions closer than this are one
ORTHOGONALITY_TOL = 1e-9  # |d_i . d_j| allowed between the channels of a triaxial accelerometer


@dataclass(frozen=True, eq=False)
class UffLayout:
    """Nodes and direction codes of a test's lines in a Universal File.

    Attributes
    ----------
    node_ids : (n_n,) int array
        Node labels: sensors' nodes from 1, exciters' nodes from the next hundred (101, 201, ...).
    node_points : (n_n, 3) array
        Node positions, m, test frame.
    node_frames : (n_n, 3, 3) array
        Each node's displacement coordinate system: columns are its local x, y, z axes in the test frame
        (a rotation; the identity for nodes in the global system).
    node_systems : (n_n,) int array
        Displacement coordinate-system number written with each node: 0 (global) or the node's id.
    sensor_nodes, sensor_codes : (n_s,) int arrays
        Node id and direction code (±1..±3 along the node's frame) of each sensor line.
    exciter_nodes, exciter_codes : (n_e,) int arrays
        Node id and direction code of each exciter line.
    """

    node_ids: np.ndarray
    node_points: np.ndarray
    node_frames: np.ndarray
    node_systems: np.ndarray
    sensor_nodes: np.ndarray
    sensor_codes: np.ndarray
    exciter_nodes: np.ndarray
    exciter_codes: np.ndarray

    def direction(self, node: int, code: int) -> np.ndarray:
        """Global unit direction of direction code ``code`` at node ``node``."""
        k = int(np.flatnonzero(self.node_ids == node)[0])
        return line_from_code(self.node_points[k], self.node_frames[k], code)


def line_from_code(point, frame, code: int) -> np.ndarray:
    """Global unit direction of a UFF direction code (±1..±3) at a node: :func:`.recording.code_direction`.

    ``point`` is the node's position (m): a Cartesian system's directions are the same everywhere; it is part
    of the signature because those of cylindrical and spherical systems are not.
    """
    return code_direction(frame, code)


def _global_codes(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Code of the global axis nearest to each unit direction (n, 3), and the distance to that axis."""
    k = np.argmax(np.abs(directions), axis=1)
    sign = np.sign(directions[np.arange(len(directions)), k])
    return (sign * (k + 1)).astype(int), np.linalg.norm(directions - sign[:, None] * AXES[k], axis=1)


def _tilted_frame(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest rotation that turns the global axis nearest to ±d onto ±d (Rodrigues), and d's code in it."""
    codes = _global_codes(d[None])[0]
    k, target = abs(codes[0]) - 1, np.sign(codes[0]) * d
    v = skew(np.cross(AXES[k], target))
    return np.eye(3) + v + v @ v / (1.0 + target[k]), codes


def _triad_frame(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Frame of a bi- or triaxial accelerometer: channel i along local axis i; a left-handed third axis flipped."""
    axes = directions if len(directions) == 3 else np.vstack([directions, np.cross(*directions)])
    flip = np.sign(np.linalg.det(axes))
    u, _, vt = np.linalg.svd((axes * np.array([1.0, 1.0, flip])[:, None]).T)
    return u @ vt, np.array([1, 2, 3 * int(flip)])[: len(directions)]


def _group_frame(directions: np.ndarray, node_systems: bool, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Frame (3, 3) and codes (k,) of the k lines of one accelerometer or exciter (one point)."""
    if len(directions) > 3:
        raise MasslineError(f"{name}: {len(directions)} channels, an accelerometer has at most three")
    cosines = np.abs(directions @ directions.T - np.eye(len(directions))).max()
    if cosines > ORTHOGONALITY_TOL:
        raise MasslineError(f"{name}: the channels are not mutually orthogonal (|cos| up to {cosines:.2g})")
    codes, off_axis = _global_codes(directions)
    if np.all(off_axis < AXIS_TOL):
        return np.eye(3), codes
    if not node_systems:
        raise MasslineError(
            f"{name} is not along a global axis: write it with node_systems=True (a coordinate system per node)"
        )
    return _tilted_frame(directions[0]) if len(directions) == 1 else _triad_frame(directions)


def _z_frame(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A frame whose +z is the unit direction ``d`` exactly, its x the global x turned the shortest way with it
    (Rodrigues; global x itself when ``d`` points nearly along −z), and ``d``'s code in it (+3)."""
    seed = AXES[0] - d[0] / (1.0 + d[2]) * np.array([d[0], d[1], 1.0 + d[2]]) if d[2] > -0.9 else AXES[0]
    x = seed - (seed @ d) * d
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(d, x), d]), np.array([3])


def _setup_frame(directions: np.ndarray, node_systems: bool, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Frame and codes of one point of a setup: a lone line along its own +z, two or three channels along x, y, z."""
    if len(directions) == 1:
        return _z_frame(directions[0])
    _group_frame(directions, node_systems, name)  # refuses what no accelerometer is
    return _triad_frame(directions)


def _line_frames(
    lines: Lines, node_systems: bool, kind: str, group_frame=_group_frame
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Point label group (n,), node point (n, 3), node frame (n, 3, 3) and direction code (n,) of every line."""
    group = point_groups(lines)
    points, frames, codes = lines.points.copy(), np.empty((len(lines), 3, 3)), np.empty(len(lines), dtype=int)
    for g in range(int(group.max(initial=-1)) + 1):
        index = np.flatnonzero(group == g)
        name = f"{kind} {', '.join(str(i + 1) for i in index)} ({lines.describe(index[0])})"
        if np.ptp(lines.points[index], axis=0).max() > POINT_TOL:
            raise MasslineError(f"{name}: the channels of one accelerometer must share one point")
        frame, group_codes = group_frame(lines.directions[index], node_systems, name)
        points[index], frames[index], codes[index] = lines.points[index[0]], frame, group_codes
    _refuse_repeats(lines, kind)
    return group, points, frames, codes


def _refuse_repeats(lines: Lines, kind: str) -> None:
    """Refuse two lines through one point along one direction: a file cannot tell them apart."""
    for i in range(len(lines)):
        same = np.flatnonzero(
            (np.abs(lines.points[:i] - lines.points[i]).max(axis=1, initial=0) <= POINT_TOL)
            & (np.abs(lines.directions[:i] - lines.directions[i]).max(axis=1, initial=0) <= SAME_DIRECTION_TOL)
        )
        if len(same):
            raise MasslineError(f"{kind}s {same[0] + 1} and {i + 1} are the same line: a file cannot tell them apart")


def uff_layout(sensors: Lines, exciters: Lines, node_systems: bool = True) -> UffLayout:
    """Nodes, frames and direction codes under which a test's lines are written.

    Parameters
    ----------
    sensors, exciters : Lines
        Sensor and exciter lines (m, test frame); lines of one triaxial accelerometer share a point.
    node_systems : bool
        Give nodes with lines off the global axes their own coordinate system. If False, every line must be
        along a ± global axis.

    Raises
    ------
    MasslineError (a ValueError)
        Non-orthogonal triaxial channels, an oblique line without node systems, or two identical lines.
    """
    return _layout(sensors, exciters, node_systems, _group_frame, own_systems=False)


def _layout(sensors: Lines, exciters: Lines, node_systems: bool, group_frame, own_systems: bool) -> UffLayout:
    """The layout with each point's frame from ``group_frame``; every node in a system of its own
    (``own_systems``) or only those whose frame is not the global one."""
    s_group, s_points, s_frames, s_codes = _line_frames(sensors, node_systems, "sensor", group_frame)
    e_group, e_points, e_frames, e_codes = _line_frames(exciters, node_systems, "exciter", group_frame)
    s_labels, e_labels = point_labels(sensors, exciters)
    s_first, e_first = np.unique(s_group, return_index=True)[1], np.unique(e_group, return_index=True)[1]
    ids = np.concatenate([s_labels[s_first], e_labels[e_first]]).astype(int)
    frames = np.concatenate([s_frames[s_first], e_frames[e_first]])
    in_global = np.all(frames == np.eye(3), axis=(1, 2)) & (not own_systems)
    return UffLayout(
        node_ids=ids,
        node_points=np.concatenate([s_points[s_first], e_points[e_first]]),
        node_frames=frames,
        node_systems=np.where(in_global, 0, ids),
        sensor_nodes=s_labels.astype(int),
        sensor_codes=s_codes,
        exciter_nodes=e_labels.astype(int),
        exciter_codes=e_codes,
    )


def setup_layout(sensors: Lines, exciters: Lines) -> UffLayout:
    """Nodes, frames and codes of a test's setup as a technician loads it (test software's geometry): every node
    in a coordinate system of its own, numbered like it; a lone accelerometer or hit is its system's +Z (code 3),
    an accelerometer of two or three channels has them along its x, y and z (a left-handed third: code -3).

    Parameters
    ----------
    sensors, exciters : Lines
        Sensor and exciter lines (m, test frame), as :func:`uff_layout` takes them.

    Raises
    ------
    MasslineError (a ValueError)
        Non-orthogonal channels at one point, or two identical lines.
    """
    return _layout(sensors, exciters, True, _setup_frame, own_systems=True)
