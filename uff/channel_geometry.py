"""Where a file's channels go when their lines change: nodes moved, coordinate systems turned, nodes added.

A channel is a node and a direction code along the node's displacement frame R (:func:`.recording.code_direction`).
Given each channel's new line (point r', direction d'), :func:`placed` finds the labels that carry it, changing
as little of the file's geometry as it can:

- a channel whose point is its node's and whose direction is ±R[:, |c|−1] keeps its node, its code signed to
  match (a polarity is a sign of the code, not of the data);
- the channels of one node that all move as one (one point, one right-handed frame holding every new axis,
  :func:`frame_holding`) move the node itself: its coordinates, and its displacement system when the frame turns;
- any other changed channel gets a node of its own at its new point (labels after the file's highest), with the
  frame nearest its node's that holds its axis: a triaxial accelerometer whose three axes are no longer
  orthogonal is written as three channels at one point.

A new frame is a new coordinate system (labels after the file's highest system and node labels); the global
frame is system 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.lines import skew
from massline.uff.recording import Channel

SAME = 1e-12  # m, and on unit directions: a line that moved less than this did not move
ORTHOGONAL = 1e-9  # |cos| between two axes of one frame


@dataclass(frozen=True, eq=False)
class NodePlace:
    """A node written at ``point`` (m, global frame) with displacement system ``system`` (0: global)."""

    node: int
    point: np.ndarray
    system: int


@dataclass(frozen=True, eq=False)
class Placement:
    """The file's labels for changed lines.

    Attributes
    ----------
    labels : dict
        {key: Channel}: the label of every channel given (``key`` as the caller gave it).
    moved : dict
        {node: NodePlace}: the file's nodes written again (a new point, or a new displacement system).
    added : list of NodePlace
        The nodes added, in label order.
    systems : dict
        {label: (3, 3) array}: the coordinate systems added (columns: the local axes in the global frame).
    """

    labels: dict
    moved: dict
    added: list
    systems: dict


def along(frame: np.ndarray, direction: np.ndarray, code: int) -> int | None:
    """The code ±|code| that reads ``direction`` in ``frame``; None when it is not along that axis."""
    axis = frame[:, abs(code) - 1]
    for sign in (1, -1):
        if np.abs(direction - sign * axis).max() <= SAME:
            return sign * abs(code)
    return None


def turned_onto(frame: np.ndarray, k: int, target: np.ndarray) -> np.ndarray:
    """``frame`` turned by the smallest rotation that takes its axis ``k`` onto unit ``target`` (Rodrigues;
    ``target`` · axis ≥ 0)."""
    axis = frame[:, k]
    v = skew(np.cross(axis, target))
    return (np.eye(3) + v + v @ v / (1.0 + axis @ target)) @ frame


def frame_holding(frame: np.ndarray, members: list[tuple[int, np.ndarray]]) -> tuple[np.ndarray, list[int]] | None:
    """A right-handed frame near ``frame`` with axis |c|−1 along ±d for each (code c, unit direction d) of
    ``members``, and the codes (each signed to the side of ``frame``'s axis); None when there is none (two
    directions on one axis, axes not orthogonal, a left-handed triad)."""
    axes, codes = {}, []
    for code, d in members:
        k = abs(code) - 1
        v = d if d @ frame[:, k] >= 0 else -d
        if k in axes and np.abs(axes[k] - v).max() > SAME:
            return None
        axes[k] = v
        codes.append(int(np.sign(v @ d)) * (k + 1))
    given = sorted(axes)
    if any(abs(axes[a] @ axes[b]) > ORTHOGONAL for a in given for b in given if a < b):
        return None
    if len(given) == 1:
        return turned_onto(frame, given[0], axes[given[0]]), codes
    out = np.zeros((3, 3))
    for k, v in axes.items():
        out[:, k] = v / np.linalg.norm(v)
    if len(given) == 2:
        c = 3 - sum(given)
        out[:, c] = np.cross(out[:, (c + 1) % 3], out[:, (c + 2) % 3])  # x = y × z, y = z × x, z = x × y
    if np.linalg.det(out) < 0:
        return None
    return out, codes


def grouped(frame: np.ndarray, members: list) -> list[list]:
    """The changed channels of one node of ``frame``, (key, code, point, direction) each, in groups that can share
    a node: one point and one frame (greedy, in order)."""
    groups: list[list] = []
    for m in members:
        for g in groups:
            if np.abs(g[0][2] - m[2]).max() <= SAME and frame_holding(frame, [(x[1], x[3]) for x in g + [m]]):
                g.append(m)
                break
        else:
            groups.append([m])
    return groups


def placed(node_ids, node_points, node_frames, node_systems, system_labels, channels: dict) -> Placement:
    """The labels of ``channels`` ({key: (Channel, new point (3,) m, new unit direction (3,))}) in the file whose
    nodes are ``node_ids`` at ``node_points`` (m) with displacement frames ``node_frames`` and systems
    ``node_systems``; ``system_labels``: the file's coordinate systems' labels."""
    index = {int(n): k for k, n in enumerate(node_ids)}
    labels, pending, at_node = {}, {}, {}
    for key, (label, point, direction) in channels.items():
        k = index[label.node]
        at_node.setdefault(label.node, []).append(key)
        code = along(node_frames[k], direction, label.code)
        if np.abs(point - node_points[k]).max() <= SAME and code is not None:
            labels[key] = Channel(label.node, code)
        else:
            pending.setdefault(label.node, []).append((key, label.code, np.asarray(point), np.asarray(direction)))
    next_node = max(map(int, node_ids), default=0) + 1
    next_system = max([*map(int, system_labels), *map(int, node_ids)], default=0) + 1
    moved, added, systems = {}, [], {}
    for node, members in pending.items():
        k = index[node]
        staying = len(at_node[node]) > len(members)
        for g, group in enumerate(grouped(node_frames[k], members)):
            frame, codes = frame_holding(node_frames[k], [(m[1], m[3]) for m in group])
            if np.abs(frame - node_frames[k]).max() <= SAME:
                system = int(node_systems[k])
            elif np.abs(frame - np.eye(3)).max() <= SAME:
                system = 0
            else:
                system, next_system = next_system, next_system + 1
                systems[system] = frame
            if g == 0 and not staying:
                label = node
                moved[node] = NodePlace(node, group[0][2], system)
            else:
                label, next_node = next_node, next_node + 1
                added.append(NodePlace(label, group[0][2], system))
            labels.update({m[0]: Channel(label, c) for m, c in zip(group, codes)})
    return Placement(labels, moved, added, systems)
