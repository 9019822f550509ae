"""The rig a technician hangs the body on: a soft cord from a hook to an apex straight above the CoG, and a bridle of
legs from the apex down to points on the body's surface.

Where the vertical through the CoG leaves the body, the cord is tied there (no legs). Elsewhere the apex A is in the
air and a bridle of three legs holds it: stiff legs (wire or rope, far stiffer than the soft cord) from three
attachment points a_i on the surface meet at A, which the tripod fixes to the body, so the body hangs as if the cord
were tied at A (the support model of :mod:`.suspension`, a cord at A). The legs carry the weight W with tensions

    Σ_i T_i e_i = W up,    e_i = (A − a_i)/|A − a_i|,

all positive only when the vertical through A (and the CoG below it) passes inside the legs' triangle; the body then
hangs level, A above the CoG. An attachment point is one a technician can use (an eyelet screwed in, a clamp, a
shackle): its leg runs clear of the body to A, rises at least ``MIN_ELEVATION`` from the horizontal, and a clamp
``ATTACH_RADIUS`` round fits along its outward normal over ``ATTACH_LENGTH`` (not inside a bore or a hole). The rig
chosen is the most evenly loaded triple (the least tension over the greatest), among the farthest points of
``SECTORS`` sectors around the vertical. Points in metres, tensions in newtons, the test frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np
import trimesh

from massline.meshes.clearance import cylinder_free, segments_clear, tangent_frames

MIN_ELEVATION = 30.0  # degrees: a leg rises at least this much from the horizontal to the apex
ATTACH_RADIUS = 5e-3  # m: a clamp or an eyelet's radius, clear around the attachment's normal
ATTACH_LENGTH = 20e-3  # m: the run a hand and a clamp need clear along that normal
SAMPLES = 3000  # surface points sampled for attachments
SECTORS = 12  # sectors around the vertical through the apex
PER_SECTOR = 4  # the farthest points of each sector kept for the choice


@dataclass(frozen=True, eq=False)
class Rig:
    """The apex (3,) m straight above the CoG; the legs' attachment points (k, 3) m on the surface, their outward
    normals (k, 3) and static tensions (k,) N; k = 0 when the cord is tied on the surface at the apex."""

    apex: np.ndarray
    attachments: np.ndarray
    normals: np.ndarray
    tensions: np.ndarray

    @property
    def lengths(self) -> np.ndarray:
        """Each leg's length (k,) m, attachment to apex."""
        return np.linalg.norm(self.apex - self.attachments, axis=1)

    def as_dict(self) -> dict:
        """plan.json's ``rig``: ``apex`` m, ``legs`` (``attachment`` m, ``normal``, ``length_m``, ``tension_n``)."""
        legs = [
            {"attachment": a.tolist(), "normal": n.tolist(), "length_m": float(length), "tension_n": float(t)}
            for a, n, length, t in zip(self.attachments, self.normals, self.lengths, self.tensions)
        ]
        return {"apex": self.apex.tolist(), "legs": legs}

    def describe(self) -> str:
        """'bridle of 3 legs to the apex (0, 0, 72) mm: from (19, 4, 60) mm, 23 mm long, 1.8 N; …', or the tie."""
        if not len(self.attachments):
            return f"the cord tied on the surface at {mm(self.apex)} mm"
        legs = "; ".join(
            f"from {mm(a)} mm, {1e3 * length:.0f} mm long, {t:.2g} N"
            for a, length, t in zip(self.attachments, self.lengths, self.tensions)
        )
        return f"bridle of {len(self.attachments)} legs to the apex {mm(self.apex)} mm: {legs}"


def mm(point: np.ndarray) -> str:
    """'(15, 29, 90)': a point in mm, to the millimetre."""
    return "(" + ", ".join(f"{np.round(1e3 * c) + 0.0:g}" for c in point) + ")"


def attachable(mesh: trimesh.Trimesh, points: np.ndarray, normals: np.ndarray, apex: np.ndarray, up) -> np.ndarray:
    """Which surface points (k, 3) with outward ``normals`` (k, 3) take a leg to ``apex`` (3,): rising at least
    ``MIN_ELEVATION``, leaving the surface outwards, clear of the body, with a clamp's room along the normal."""
    span = apex - points
    e = span / np.maximum(np.linalg.norm(span, axis=1, keepdims=True), 1e-300)
    ok = (e @ up >= np.sin(np.radians(MIN_ELEVATION))) & (np.einsum("kd,kd->k", e, normals) > 0.1)
    index = np.flatnonzero(ok)
    roomy = cylinder_free(mesh, points[index], normals[index], ATTACH_RADIUS, ATTACH_LENGTH) >= ATTACH_LENGTH
    index = index[roomy]
    ok[:] = False
    ok[index[segments_clear(mesh, points[index], np.tile(apex, (len(index), 1)))]] = True
    return ok


def shortlist(points: np.ndarray, apex: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Indices of the ``PER_SECTOR`` points farthest from the vertical through ``apex`` in each of ``SECTORS``
    sectors around it."""
    u, v = tangent_frames(up[None])
    flat = points - apex
    x, y = flat @ u[0], flat @ v[0]
    sector = np.floor((np.arctan2(y, x) + np.pi) / (2 * np.pi) * SECTORS).astype(int) % SECTORS
    arm = np.hypot(x, y)
    kept = [np.flatnonzero(sector == s)[np.argsort(-arm[sector == s])[:PER_SECTOR]] for s in range(SECTORS)]
    return np.concatenate(kept)


def leg_tensions(points: np.ndarray, apex: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """Tensions (m, 3) N of the triples of legs (m, 3, 3 attachment points) meeting at ``apex`` that carry ``weight``
    (3,) N (up): Σ T_i e_i = weight; NaN where the three legs lie in one plane."""
    e = apex - points
    e /= np.linalg.norm(e, axis=2, keepdims=True)
    matrices = np.transpose(e, (0, 2, 1))  # columns e_i
    solvable = np.abs(np.linalg.det(matrices)) > 1e-6
    out = np.full((len(points), 3), np.nan)
    out[solvable] = np.linalg.solve(matrices[solvable], np.tile(weight, (int(solvable.sum()), 1))[..., None])[..., 0]
    return out


def rig(mesh: trimesh.Trimesh, apex: np.ndarray, weight: float, up, on_surface: bool) -> Rig | None:
    """The rig (:class:`Rig`) of a cord tied at ``apex`` (3,) m straight above the CoG: the cord alone where the apex
    is on the surface (``on_surface``), else the most evenly loaded bridle of three legs carrying ``weight`` N;
    None when no three attachment points hold the apex."""
    up = np.asarray(up, dtype=float)
    apex = np.asarray(apex, dtype=float)
    if on_surface:
        return Rig(apex, np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0))
    points, faces = trimesh.sample.sample_surface(mesh, SAMPLES, seed=0)
    normals = mesh.face_normals[faces]
    ok = np.flatnonzero(attachable(mesh, points, normals, apex, up))
    if len(ok) < 3:
        return None
    pick = ok[shortlist(points[ok], apex, up)]
    triples = np.array(list(combinations(range(len(pick)), 3)))
    tensions = leg_tensions(points[pick][triples], apex, weight * up)
    balance = np.nan_to_num(tensions.min(axis=1) / tensions.max(axis=1), nan=-np.inf)
    best = int(np.argmax(balance))
    if not balance[best] > 0:
        return None
    chosen = pick[triples[best]]
    return Rig(apex, points[chosen], normals[chosen], tensions[best])
