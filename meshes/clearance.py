"""Free space around a surface point: how far a cylinder or a ray goes from it before it meets the body.

A hammer swinging in along a point's normal, an accelerometer's housing standing on it, its cable leaving sideways,
a bridle's leg running from it to the apex: each needs a volume of air that the body must not cross. These are
ray casts against the closed mesh (trimesh's ray engine, Embree where installed), all the points' rays in one call.

A cylinder of radius ρ along the unit axis a from the surface point p (outward normal n, a · n > 0) is probed by
rays: along a from its centre and from ``RIM_RAYS`` points of its rim, p + ε a + ρ (cos φ u + sin φ v), and by
``RIM_RAYS`` spokes from its lifted centre out to the rim (a wall nearer than ρ, whose inside the rim rays would
start in). The rays start ``LIFT`` off the surface, so that the facet a point lies on is not met. Its free length is
the shortest distance its rays travel before they meet the body (``length`` when none does within it); 0 when a
spoke meets the body. Lengths in metres, mesh frame.
"""

from __future__ import annotations

import numpy as np
import trimesh

RIM_RAYS = 8  # rays around a cylinder's rim, and spokes to it
LIFT = 0.2e-3  # m: rays start this far off the surface (the facet under a point is not met)


def tangent_frames(axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (n, 3) each, orthogonal to each other and to the unit ``axes`` (n, 3)."""
    helper = np.where(np.abs(axes[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(axes, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u, np.cross(axes, u)


def free_lengths(mesh: trimesh.Trimesh, origins: np.ndarray, directions: np.ndarray, length: float) -> np.ndarray:
    """How far (m) each ray (origins, unit directions, (k, 3)) goes before it meets the body, ``length`` at most."""
    out = np.full(len(origins), float(length))
    if not len(origins):
        return out
    where, ray, _ = mesh.ray.intersects_location(origins, directions, multiple_hits=False)
    if len(ray):
        t = np.einsum("kd,kd->k", where - origins[ray], directions[ray])
        np.minimum.at(out, ray, np.clip(t, 0.0, length))
    return out


def rim(axes: np.ndarray, radius: float) -> np.ndarray:
    """Offsets (n, RIM_RAYS, 3) m from a cylinder's centre to ``RIM_RAYS`` points of its rim, about unit ``axes``."""
    u, v = tangent_frames(axes)
    phi = 2 * np.pi * np.arange(RIM_RAYS) / RIM_RAYS
    return radius * (np.cos(phi)[None, :, None] * u[:, None, :] + np.sin(phi)[None, :, None] * v[:, None, :])


def cylinder_free(
    mesh: trimesh.Trimesh, points: np.ndarray, axes: np.ndarray, radius: float, length: float
) -> np.ndarray:
    """Free length (m, up to ``length``) of the cylinder of ``radius`` (m) along each unit axis (n, 3) from each
    surface point (n, 3): 0 where the body comes nearer than ``radius`` to the axis at the surface (a spoke meets
    it), else the shortest way its centre and rim rays go clear."""
    n = len(points)
    if not n:
        return np.zeros(0)
    start = points + LIFT * axes
    offsets = rim(axes, radius)
    spokes = free_lengths(
        mesh, np.repeat(start, RIM_RAYS, axis=0), (offsets / radius).reshape(-1, 3), radius
    ).reshape(n, RIM_RAYS)
    origins = np.concatenate([start[:, None, :], start[:, None, :] + offsets], axis=1).reshape(-1, 3)
    along = free_lengths(mesh, origins, np.repeat(axes, RIM_RAYS + 1, axis=0), length).reshape(n, RIM_RAYS + 1)
    return np.where(spokes.min(axis=1) < radius, 0.0, along.min(axis=1))


def side_free(
    mesh: trimesh.Trimesh, points: np.ndarray, axes: np.ndarray, height: float, length: float
) -> tuple[np.ndarray, np.ndarray]:
    """Sideways from ``height`` (m) up each unit axis (n, 3) above each point (n, 3): the longest free run (m, up to
    ``length``) among ``RIM_RAYS`` directions square to the axis, and that direction (n, 3) (a cable's exit)."""
    n = len(points)
    if not n:
        return np.zeros(0), np.zeros((0, 3))
    directions = rim(axes, 1.0)
    origins = np.repeat(points + height * axes, RIM_RAYS, axis=0)
    free = free_lengths(mesh, origins, directions.reshape(-1, 3), length).reshape(n, RIM_RAYS)
    best = np.argmax(free, axis=1)
    return free[np.arange(n), best], directions[np.arange(n), best]


def segments_clear(mesh: trimesh.Trimesh, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Whether each straight segment from a surface point (k, 3), lifted ``LIFT`` towards its end, to its end (k, 3)
    crosses no part of the body (a bridle's leg to its apex)."""
    span = ends - starts
    length = np.linalg.norm(span, axis=1)
    direction = span / np.maximum(length, 1e-300)[:, None]
    origins = starts + LIFT * direction
    return free_lengths(mesh, origins, direction, float(length.max(initial=0.0))) >= length - LIFT
