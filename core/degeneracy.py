"""Why a layout is singular, in words a test engineer can act on.

A set of sensor lines S sees the rigid motion q = (a_O, α) unless S q = 0. The
null space of S is therefore the motion the layout cannot see: a translation
(α = 0), a rotation about a line (zero pitch) or a screw. Exciter sets are
explained by their directions and points.
"""

from __future__ import annotations

import numpy as np

from massline.core.linear_system import RANK_TOLERANCE
from massline.core.lines import Lines
from massline.core.numbers import number, vector_text


def distinct_points(lines: Lines, tol: float = 1e-9) -> np.ndarray:
    """The distinct points the lines are anchored at."""
    scale = max(1.0, float(np.abs(lines.points).max(initial=0.0)))
    keys = np.round(lines.points / (tol * scale)).astype(np.int64)
    return lines.points[np.unique(keys, axis=0, return_index=True)[1]]


def parallel_direction(lines: Lines, tol: float = 1e-9) -> np.ndarray | None:
    """The common direction when every line is parallel to one, else None."""
    d0 = lines.directions[0]
    return d0 if np.all(np.linalg.norm(np.cross(lines.directions, d0), axis=1) < tol) else None


def describe_motion(q: np.ndarray, length_scale: float) -> str:
    """Put a rigid motion q = (a_O, α) into words: translation, rotation or screw."""
    a, alpha = q[:3], q[3:]
    if np.linalg.norm(alpha) * length_scale < 1e-6 * np.linalg.norm(a):
        return f"translation along {vector_text(a / np.linalg.norm(a))} is unseen"
    u = alpha / np.linalg.norm(alpha)
    point = np.cross(alpha, a) / (alpha @ alpha)
    pitch = (alpha @ a) / (alpha @ alpha)
    if abs(pitch) < 1e-6 * length_scale:
        return f"rotation about the line through {vector_text(point)} m along {vector_text(u)} is unseen"
    return f"a screw motion about the line through {vector_text(point)} m along {vector_text(u)} (pitch {number(pitch, 3)} m) is unseen"


def unseen_motion(lines: Lines) -> str:
    """Why sensor lines fail to see all six rigid motions (rank S < 6)."""
    n = len(lines)
    if n < 6:
        return f"{n} sensor lines cannot see 6 rigid-body motions; at least 6 are needed"
    S = lines.coordinates
    _, s, Vt = np.linalg.svd(S)
    rank = int(np.sum(s > RANK_TOLERANCE * s[0]))
    points = distinct_points(lines)
    scale = max(float(np.ptp(lines.points, axis=0).max()), 1e-3)
    words = describe_motion(Vt[rank], scale)
    if 6 - rank > 1:
        words += f" (and {5 - rank} more motions)"
    if len(points) == 1:
        hint = "all sensors sit at one point, so no rotation about it is seen"
    elif len(points) == 2:
        hint = "all sensors sit at two points (e.g. two triaxials): rotation about the line joining them is unseen"
    elif (d := parallel_direction(lines)) is not None:
        hint = f"every sensor is parallel to {vector_text(d)}"
    else:
        hint = "every sensor line meets that line or is parallel to it"
    return f"{words}; {hint}. Add a sensor off that line / in another direction"


def exciter_hint(exciters: Lines) -> str:
    """Why exciters may leave the dynamic equations singular."""
    if (d := parallel_direction(exciters)) is not None:
        return (
            f"all {len(exciters)} exciters are parallel to {vector_text(d)}, so the inertia about that direction "
            "is never excited; hit in at least two non-parallel directions (the paper uses x, y and z)"
        )
    if len(distinct_points(exciters)) == 1:
        return "all exciters act at one point; hit at least two points"
    return "the exciter lines are too few or too alike; add hits at other points and in other directions"
