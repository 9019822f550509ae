"""Where a support meets the body's surface: the cord's tie point above the CoG, the pad's contact points.

Points in m, in the test frame; ``up`` is the unit vector opposite to gravity (:mod:`.suspension`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay

UP = np.array([0.0, 0.0, 1.0])


def ray_hits(triangles: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Points where the ray origin + t·direction (t ≥ 0) crosses the triangles (k, 3, 3), Möller–Trumbore."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    e1, e2 = b - a, c - a
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-14 * np.einsum("ij,ij->i", e1, e1)
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ direction) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0)
    return origin + t[hit, None] * direction


def point_above(mesh, point: np.ndarray, up=UP) -> tuple[np.ndarray, bool]:
    """Where a cord over ``point`` (the CoG) is tied, m, and whether that is on the surface.

    The highest surface point straight above; where nothing of the body lies above the
    CoG, the apex of a bridle of slings: the point above the CoG level with the body's top.
    """
    up = np.asarray(up, dtype=float)
    hits = ray_hits(mesh.triangles, point, up)
    if len(hits):
        return hits[np.argmax(hits @ up)], True
    return point + (np.max(mesh.vertices @ up) - point @ up) * up, False


def lowest_points(mesh, cog=None, up=UP, depth: float = 1e-3) -> np.ndarray:
    """Vertices within ``depth`` (m) of the body's lowest level along ``up``: where it rests on a pad.

    A body that meets the pad at a corner or an edge sinks into it until it bears on an area: the depth
    doubles until the contact points span one (at least 3, not on a line) and, given the ``cog`` (m), until
    that area holds the CoG above it (the body rests without tipping), up to a tenth of the body's height.
    """
    up = np.asarray(up, dtype=float)
    heights = mesh.vertices @ up
    while True:
        points = mesh.vertices[heights <= heights.min() + depth]
        if cog is not None and len(points) >= 3:
            points = lifted_off(points, np.asarray(cog, dtype=float), up)
        if bears(points, cog, up, 1e-3 * np.ptp(heights)):
            return points
        if depth >= 0.1 * np.ptp(heights):
            return points if cog is None else shimmed_pads(mesh.vertices, np.asarray(cog, dtype=float), up)
        depth *= 2


def shimmed_pads(vertices: np.ndarray, cog: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Four pads around the CoG, each under the lowest vertex of its quadrant (as seen from above): how a
    body that would tip over on one pad is set on several, each shimmed to its height."""
    flat = vertices - cog - np.outer((vertices - cog) @ up, up)
    helper = np.eye(3)[np.argmin(np.abs(up))]
    e1 = np.cross(up, helper)
    e1 /= np.linalg.norm(e1)
    angle = np.arctan2(flat @ np.cross(up, e1), flat @ e1)
    quadrant = np.floor((angle + np.pi) / (np.pi / 2)).astype(int) % 4
    heights = vertices @ up
    pads = [vertices[quadrant == q][np.argmin(heights[quadrant == q])] for q in range(4) if np.any(quadrant == q)]
    return np.array(pads)


def lifted_off(points: np.ndarray, cog: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The contact points that stay pressed when equal pad springs carry the weight: the least-norm
    reactions (those of equal springs) are found, points pulled (negative) lift off, and again until none."""
    while len(points) >= 3:
        wrenches = np.vstack([np.tile(up[:, None], len(points)), np.cross(points - cog, up).T])
        reactions = np.linalg.lstsq(wrenches, np.concatenate([up, np.zeros(3)]), rcond=None)[0]
        if reactions.min() >= -1e-9:
            break
        points = points[reactions > reactions.min()]
    return points


def bears(points: np.ndarray, cog, up: np.ndarray, tolerance: float) -> bool:
    """Whether contact ``points`` span an area (wider than ``tolerance``, m) holding ``cog`` (if given) above it."""
    if len(points) < 3:
        return False
    flat = points - np.outer(points @ up, up)
    middle = flat.mean(axis=0)
    _, spread, axes = np.linalg.svd(flat - middle, full_matrices=False)
    if spread[1] <= tolerance:
        return False
    if cog is None:
        return True
    centre = np.asarray(cog, dtype=float) - (np.asarray(cog) @ up) * up
    return bool(Delaunay((flat - middle) @ axes[:2].T).find_simplex((centre - middle) @ axes[:2].T) >= 0)
