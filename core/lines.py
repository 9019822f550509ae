"""Sensor and exciter lines as 6-vectors (Plücker coordinates).

A uniaxial accelerometer or a hammer hit is a *line*: a point r (m) and a unit
direction d, both in the one test frame O xyz. Its 6-vector is

    ℓ = (d, r × d)

so that an accelerometer reads ℓ · q for the rigid-body acceleration
q = (a_O, α) at O, and a unit force along the line is the wrench ℓ about O
(DESIGN.md, "Conventions"). Only the line matters, not where on it r sits:
every formula of the paper can be written with ℓ alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError
from massline.core.numbers import vector_text

AXES = np.eye(3)
AXIS_NAMES = ("x", "y", "z")


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrix [v]×, so that ``skew(v) @ w == np.cross(v, w)``."""
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def cross(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    """a × b along ``axis`` (of length 3) for arrays of any shape that broadcast: ``np.cross`` without its
    per-call overhead (moveaxis and checks), which dominated the diagnosis's fits of small layouts."""
    a, b = np.moveaxis(a, axis, 0), np.moveaxis(b, axis, 0)
    product = np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])
    return np.moveaxis(product, 0, axis)


def perpendicular_bases(directions: np.ndarray) -> np.ndarray:
    """T_i (n, 3, 2): two unit vectors ⊥ each direction d_i, the axes a sensor's transverse reading lies on."""
    helper = np.eye(3)[np.argmin(np.abs(directions), axis=1)]
    t1 = cross(directions, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, cross(directions, t1)], axis=2)


@dataclass(frozen=True, eq=False)
class Lines:
    """An ordered set of lines: points (n, 3) in m and unit directions (n, 3).

    ``triaxial`` holds, for each line, the index of the triaxial accelerometer it
    belongs to, or -1 for a uniaxial one.
    """

    points: np.ndarray
    directions: np.ndarray
    triaxial: np.ndarray | None = None

    def __post_init__(self):
        points = np.atleast_2d(np.asarray(self.points, dtype=float))
        directions = np.atleast_2d(np.asarray(self.directions, dtype=float))
        if points.shape != directions.shape or points.shape[1:] != (3,):
            raise MasslineError(
                f"lines need points and directions of shape (n, 3), got {points.shape} and {directions.shape}"
            )
        if not (np.isfinite(points).all() and np.isfinite(directions).all()):
            raise MasslineError("a line has a NaN or infinite coordinate: check the point and direction list")
        norms = np.linalg.norm(directions, axis=1)
        if np.any(norms < 1e-12):
            raise MasslineError("a line has a zero direction vector: give every sensor and exciter a direction")
        group = np.full(len(points), -1) if self.triaxial is None else np.asarray(self.triaxial, dtype=int)
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "directions", directions / norms[:, None])
        object.__setattr__(self, "triaxial", group)

    @classmethod
    def along_axes(cls, points, axes) -> "Lines":
        """Lines through ``points`` along coordinate axes (0 = x, 1 = y, 2 = z)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        return cls(points, AXES[np.asarray(axes, dtype=int)])

    @classmethod
    def triaxials(cls, points) -> "Lines":
        """One triaxial accelerometer (x, y, z lines through one point) per point."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        n = len(points)
        return cls(np.repeat(points, 3, axis=0), np.tile(AXES, (n, 1)), np.repeat(np.arange(n), 3))

    def __len__(self) -> int:
        return len(self.points)

    def __getitem__(self, index) -> "Lines":
        index = np.atleast_1d(np.arange(len(self))[index])
        return Lines(self.points[index], self.directions[index], self.triaxial[index])

    def __add__(self, other: "Lines") -> "Lines":
        offset = self.triaxial.max(initial=-1) + 1
        other_group = np.where(other.triaxial >= 0, other.triaxial + offset, -1)
        return Lines(
            np.vstack([self.points, other.points]),
            np.vstack([self.directions, other.directions]),
            np.concatenate([self.triaxial, other_group]),
        )

    @property
    def moments(self) -> np.ndarray:
        """r × d for each line (m), shape (n, 3)."""
        return np.cross(self.points, self.directions)

    @property
    def coordinates(self) -> np.ndarray:
        """The 6-vectors ℓ = (d, r × d), shape (n, 6)."""
        return np.hstack([self.directions, self.moments])

    def transformed(self, rotation: np.ndarray, translation: np.ndarray) -> "Lines":
        """The same physical lines seen in a frame where x' = R x + t."""
        return Lines(self.points @ rotation.T + translation, self.directions @ rotation.T, self.triaxial)

    def scaled(self, length: float) -> "Lines":
        """The same lines with lengths multiplied by ``length`` (a change of unit)."""
        return Lines(self.points * length, self.directions, self.triaxial)

    def describe(self, i: int) -> str:
        """A short human label: '+y at (0.1, 0.02, 0) m'; an oblique direction as its vector."""
        d = self.directions[i]
        k = int(np.argmax(np.abs(d)))
        name = ("+" if d[k] > 0 else "-") + AXIS_NAMES[k] if abs(abs(d[k]) - 1) < 1e-9 else vector_text(d, 3)
        return f"{name} at {vector_text(self.points[i])} m"
