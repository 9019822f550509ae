"""What the identification report's pictures show: the body, the test's channels, the identified CoG and axes.

Geometry only, in the recording's frame (the mesh's, when one is given), in metres. The body is the
nominal mesh or, without one, a stand-in: the convex hull of the test points. It is drawn translucent so
that the principal axes, arrows from the identified CoG along each axis as long as the radius of
gyration about it, show through. Accelerometers and hits are numbered by their UFF node, as the
diagnosis names them ("sensor 5:+Z" is the blue 5); channels a finding names are drawn in their own colour.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import trimesh

from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.reports.plan_scene import AXIS, FLAGGED, HIT, Marker, Scene, scene_of

OPACITY = 0.4  # of the body's surface: the principal axes inside it stay in sight
FLAT = 0.05  # a point cloud thinner than this fraction of its size in some direction is flat
THICKNESS = 0.03  # the stand-in of a flat cloud is this fraction of its size thick


def stand_in(points: np.ndarray) -> trimesh.Trimesh:
    """A closed surface around the test points (n, 3), m: their convex hull, given some thickness when flat."""
    points = np.unique(np.asarray(points, dtype=float), axis=0)
    centred = points - points.mean(axis=0)
    _, spread, axes = np.linalg.svd(centred, full_matrices=False)
    size = float(np.ptp(points, axis=0).max()) or 1.0
    for k in range(3):
        if k >= len(spread) or spread[k] < FLAT * spread[0]:
            offset = THICKNESS * size / 2 * axes[k] if k < len(axes) else THICKNESS * size / 2 * np.eye(3)[k]
            points = np.vstack([points + offset, points - offset])
    return trimesh.convex.convex_hull(points)


def principal_frame(body: RigidBody, planar: bool) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (k,) ascending and axes (3, k) as columns, each turned to point along its largest
    component's + side; for a plate the two in-plane ones (the others are not identified)."""
    if planar:
        moments, inplane = np.linalg.eigh(body.inertia_cog[:2, :2])
        axes = np.vstack([inplane, np.zeros((1, 2))])
    else:
        moments, axes = body.principal_moments, body.principal_axes.copy()
    for k in range(axes.shape[1]):
        axes[:, k] *= np.sign(axes[np.argmax(np.abs(axes[:, k])), k])
    return np.asarray(moments, dtype=float), axes


def axis_markers(body: RigidBody, planar: bool) -> tuple[list[Marker], list[np.ndarray]]:
    """The principal axes as markers "I1", "I2", … at the CoG, and their arrows (1, 2, 3): from the CoG along
    the axis, as long as the radius of gyration about it (√(I_k/m))."""
    moments, axes = principal_frame(body, planar)
    markers, arrows = [], []
    for k in range(axes.shape[1]):
        radius = np.sqrt(max(moments[k], 0.0) / body.mass)
        markers.append(Marker(f"I{k + 1}", AXIS, body.cog, axes[:, k][None], (k,)))
        arrows.append(np.array([[body.cog, body.cog + radius * axes[:, k]]]))
    return markers, arrows


def identification_scene(
    mesh: trimesh.Trimesh | None,
    sensors: Lines,
    exciters: Lines,
    sensor_names: list,
    hit_names: list,
    body: RigidBody,
    planar: bool,
    flagged_sensors=(),
    flagged_hits=(),
) -> Scene:
    """The scene of an identified test: the body (or the stand-in hull) translucent, the channels numbered by
    node, the ones a finding names (sensor line and hit indices, 0-based) flagged, and the principal axes of
    ``body`` at its CoG."""
    if mesh is None:
        mesh = stand_in(np.vstack([sensors.points, exciters.points]))
    scene = scene_of(mesh, sensors, exciters, body.cog)
    markers = []
    for marker in scene.markers:
        names = hit_names if marker.kind == HIT else sensor_names
        node = names[marker.lines[0]].node
        flagged = set(marker.lines) & set(flagged_hits if marker.kind == HIT else flagged_sensors)
        markers.append(
            replace(marker, label=marker.label if node is None else str(node), kind=FLAGGED if flagged else marker.kind)
        )
    extra, arrows = axis_markers(body, planar)
    return replace(
        scene,
        markers=markers + extra,
        normals=np.vstack([scene.normals, np.zeros((len(extra), 3))]),
        faces=np.concatenate([scene.faces, np.full(len(extra), -1)]),
        arrows=scene.arrows + arrows,
        opacity=OPACITY,
    )
