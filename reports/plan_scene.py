"""What the report's pictures show: the body, its numbered accelerometers and hits, their arrows.

Geometry only, in the mesh's frame O xyz and in metres: the plan's lines are
grouped into markers (a triaxial accelerometer is one marker with three
directions), each marker is put on the face it sits on, and its arrows are laid
outside the body.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from massline.core.numbering import point_labels
from massline.core.lines import Lines

ARROW = 0.16  # arrow length, fraction of the body's largest extent
SENSOR, HIT = "sensor", "hit"
AXIS, FLAGGED = "axis", "flagged"  # the identification report's principal axes, and a channel a finding names
ADDED = "added"  # an accelerometer or hit a next run adds to the first run's
COLOURS = {
    SENSOR: (31, 95, 180), HIT: (200, 40, 30), AXIS: (20, 135, 60), FLAGGED: (225, 110, 0), ADDED: (150, 40, 170),
}  # RGB  # fmt: skip


@dataclass(frozen=True, eq=False)
class Marker:
    """One accelerometer (one number for 1 or 3 measuring lines) or one hammer hit.

    Attributes
    ----------
    label : str
        The point's label: "1", "2", … for accelerometers, "101", … for hits (:mod:`massline.core.numbering`).
    kind : str
        ``SENSOR`` or ``HIT``.
    point : (3,) array
        Mounting or hit point, m.
    directions : (k, 3) array
        Unit measuring (or force) directions, k = 1 or 3.
    lines : tuple of int
        Indices of its lines in the plan's sensor (or exciter) list.
    """

    label: str
    kind: str
    point: np.ndarray
    directions: np.ndarray
    lines: tuple[int, ...]


@dataclass(frozen=True, eq=False)
class Scene:
    """What the pictures show: the body (m), its markers and CoG, and each marker's face and arrows.

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Closed surface, m, frame O xyz.
    markers : list of Marker
        Accelerometers, then hits.
    cog : (3,) array
        Nominal centre of gravity, m.
    normals, faces : (n, 3) array, (n,) int array
        Outward normal and triangle index of the face each marker sits on.
    arrows : list of (k, 2, 3) arrays
        Each marker's arrows, tail and tip, m.
    length : float
        Length of a uniaxial marker's arrow, m.
    opacity : float
        Of the body's surface: below 1 it shows what lies inside (the principal axes at the CoG).
    rig : (k, 2, 3) array
        The support's cord and bridle legs, each from its end on the body (or the apex) to the apex (or the
        hook's side), m; none when the plan keeps no rig.
    """

    mesh: trimesh.Trimesh
    markers: list[Marker]
    cog: np.ndarray
    normals: np.ndarray
    faces: np.ndarray
    arrows: list[np.ndarray]
    length: float
    opacity: float = 1.0
    rig: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 3)))


def markers_of(sensors: Lines, exciters: Lines) -> list[Marker]:
    """Accelerometers then hammer hits, one marker per point, labelled by the test's numbering
    (:mod:`massline.core.numbering`: accelerometers from 1, hits from 101)."""
    markers = []
    for kind, lines, labels in zip((SENSOR, HIT), (sensors, exciters), point_labels(sensors, exciters)):
        for label in dict.fromkeys(labels.tolist()):
            idx = np.flatnonzero(labels == label)
            markers.append(Marker(str(label), kind, lines.points[idx[0]], lines.directions[idx], tuple(idx.tolist())))
    return markers


def outward_normals(mesh: trimesh.Trimesh, markers: list[Marker]) -> tuple[np.ndarray, np.ndarray]:
    """The face each marker sits on: outward unit normals (n, 3) and triangle indices (n,).

    The nearest triangle to the marker's point; on an edge or a corner, of the
    triangles touching the point, the one whose normal is most nearly along one
    of the marker's directions (the face it is glued on or hit on).
    """
    tolerance = 1e-6 * float(mesh.extents.max())
    normals, faces = [], []
    for m in markers:
        near = trimesh.triangles.closest_point(mesh.triangles, np.tile(m.point, (len(mesh.faces), 1)))
        distance = np.linalg.norm(near - m.point, axis=1)
        touching = np.flatnonzero(distance <= distance.min() + tolerance)
        along = np.abs(mesh.face_normals[touching] @ m.directions.T).max(axis=1)
        faces.append(int(touching[np.argmax(along)]))
        normals.append(mesh.face_normals[faces[-1]])
    return np.array(normals).reshape(-1, 3), np.array(faces, dtype=int)


def face_name(normal: np.ndarray) -> str:
    """'+x face', '−z face', … for a normal within ~25° of an axis; 'oblique' otherwise."""
    k = int(np.argmax(np.abs(normal)))
    if abs(normal[k]) < 0.9:
        return "oblique"
    return f"{'+' if normal[k] > 0 else '−'}{'xyz'[k]} face"


def arrows_of(marker: Marker, normal: np.ndarray, length: float, sensor_points: np.ndarray) -> np.ndarray:
    """The marker's arrows (k, 2, 3): tail and tip in m, drawn outside the body.

    ``normal`` is the outward normal of the face the marker sits on. An
    accelerometer's arrow points along its measuring direction, from the point
    when that side is outside, else up to the point. A hit's arrow ends at the
    point, coming from outside, like the hammer; where the hit shares its point
    with an accelerometer it is moved aside by a third of its length.
    """
    p, arrows = marker.point, []
    size = length if marker.directions.shape[0] == 1 else 0.75 * length
    for d in marker.directions:
        outward = d @ normal > -1e-9
        if marker.kind == SENSOR:
            arrows.append((p, p + size * d) if outward else (p - size * d, p))
            continue
        base = p
        if len(sensor_points) and np.linalg.norm(sensor_points - p, axis=1).min() < 0.2 * length:
            side = np.cross(d, np.eye(3)[int(np.argmin(np.abs(d)))])
            base = p + length / 3 * side / np.linalg.norm(side)
        arrows.append((base + size * d, base) if outward else (base - size * d, base))
    return np.array(arrows)


def outer_end(marker: Marker, arrows: np.ndarray) -> np.ndarray:
    """The end of the marker's arrows (k, 2, 3) farthest from its point, m: where its label goes."""
    ends = arrows.reshape(-1, 3)
    return ends[np.argmax(np.linalg.norm(ends - marker.point, axis=1))]


def scene_of(mesh: trimesh.Trimesh, sensors: Lines, exciters: Lines, cog: np.ndarray) -> Scene:
    """The scene of a plan: markers numbered, placed on their faces, with arrows ``ARROW`` × the body long."""
    markers = markers_of(sensors, exciters)
    normals, faces = outward_normals(mesh, markers)
    length = ARROW * float(mesh.extents.max())
    arrows = [arrows_of(m, n, length, sensors.points) for m, n in zip(markers, normals)]
    return Scene(mesh, markers, np.asarray(cog, dtype=float), normals, faces, arrows, length)


CORD_DRAWN = 0.35  # of the body's largest extent: how much of the cord above the apex the pictures show


def rig_segments(rig: dict | None, mesh: trimesh.Trimesh) -> np.ndarray:
    """The rig of plan.json (``rig``: apex and legs, m) as segments (k, 2, 3) m: each leg from its attachment to
    the apex, and the cord from the apex up ``CORD_DRAWN`` × the body's size towards its hook."""
    if not rig or "apex" not in rig:
        return np.zeros((0, 2, 3))
    apex = np.asarray(rig["apex"], dtype=float)
    legs = [(np.asarray(leg["attachment"], dtype=float), apex) for leg in rig.get("legs", [])]
    cord = (apex, apex + np.array([0.0, 0.0, CORD_DRAWN * float(mesh.extents.max())]))
    return np.array(legs + [cord]).reshape(-1, 2, 3)
