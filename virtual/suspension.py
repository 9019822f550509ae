"""How the body is held during the test: cords and springs, or a foam pad (Appendix A).

A suspended body is not free: each cord adds an axial stiffness k along itself
and a pendulum ("string") stiffness T/L across it at its attachment point, and
gravity adds the restoring moment m·g·h of a pendulum whose pivot sits h above
the CoG. These give the suspension modes of zone A below the massline band.

All quantities are in SI and in the test frame O xyz; ``up`` is the unit vector
opposite to gravity. Rigid-body coordinates are q = (u_O, φ) at O, as in
DESIGN.md, so a point r moves by u(r) = u_O + φ × r = P(r) q with
P(r) = [I, −[r]×].
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.linalg import eigh

from massline.core.numbers import vector_text
from massline.core.errors import MasslineError, param
from massline.core.lines import skew
from massline.core.rigid_body import RigidBody
from massline.virtual.attachment import UP, lowest_points, point_above

GRAVITY = 9.80665  # m/s², standard gravity
MAX_TILT = 2.0  # degrees a body may settle out of level on its supports
STRETCH = 0.25  # m: static stretch of the recommended cord under the weight (bounce at √(g/stretch)/2π ≈ 1 Hz)
CORD_LENGTH = 1.0  # m: hanging length of the recommended cord (pendulum modes at √(g/L)/2π ≈ 0.5 Hz)
FOAM_BOUNCE = 4.0  # Hz: the bounce of the default foam pad


def point_map(r: np.ndarray) -> np.ndarray:
    """P(r) = [I, −[r]×]: displacement of point r (3,) per rigid coordinate q = (u_O, φ), shape (3, 6)."""
    return np.hstack([np.eye(3), -skew(r)])


def cord_stiffness(direction: np.ndarray, axial: float, tension: float, length: float) -> np.ndarray:
    """Stiffness (N/m, 3×3) a cord adds at its attachment point.

    k e eᵀ along the cord (unit direction e, attachment → hook) and the string
    stiffness T/L (I − e eᵀ) across it (tension T in N, hanging length L in m).
    """
    e = direction / np.linalg.norm(direction)
    along = np.outer(e, e)
    return axial * along + tension / length * (np.eye(3) - along)


def load_stiffness(force: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Rotational stiffness (N·m/rad, 3×3) of a dead load ``force`` (N) applied at ``point`` (m).

    From the second-order displacement ½ φ × (φ × r) of a body-fixed point:
    V = −F·u gives K_φφ = (F·r) I − sym(F rᵀ). Gravity at the CoG plus the
    support reactions at their points sum to m·g·h on pitch and roll for a
    pivot h above the CoG (Appendix A).
    """
    return float(force @ point) * np.eye(3) - 0.5 * (np.outer(force, point) + np.outer(point, force))


@dataclass(frozen=True)
class Cord:
    """An elastic cord or spring from a fixed hook to an attachment point on the body.

    Attributes
    ----------
    attachment : (3,) array
        Attachment point on the body, m.
    stiffness : float
        Axial stiffness, N/m.
    length : float
        Hanging length from the attachment to the hook, m (sets the pendulum stiffness T/L).
    direction : (3,) array or None
        Unit vector from the attachment towards the hook; ``None`` means straight up.
    """

    attachment: np.ndarray
    stiffness: float
    length: float
    direction: np.ndarray | None = None

    def __post_init__(self):
        object.__setattr__(self, "attachment", np.asarray(self.attachment, dtype=float))
        if not (self.stiffness > 0 and self.length > 0):
            raise MasslineError(f"cords need a positive stiffness and length, not k={self.stiffness}, L={self.length}")

    @classmethod
    def soft(cls, attachment, mass: float, stretch: float = STRETCH, length: float = CORD_LENGTH) -> "Cord":
        """Appendix A's soft cord: stretched ``stretch`` m by the weight of ``mass`` kg (k = m g / stretch, bounce
        at √(g/stretch)/2π), ``length`` m long (pendulum modes at √(g/L)/2π)."""
        return cls(attachment, mass * GRAVITY / stretch, length)


@dataclass(frozen=True)
class Foam:
    """A soft foam pad under the body: springs at the contact points.

    Attributes
    ----------
    points : (k, 3) array
        Contact points on the body's underside, m.
    stiffness : float
        Total stiffness normal to the pad (along ``up``), N/m, shared equally by the points.
    shear_ratio : float
        Tangential over normal stiffness of the foam.
    """

    points: np.ndarray
    stiffness: float
    shear_ratio: float = 0.5

    def __post_init__(self):
        object.__setattr__(self, "points", np.atleast_2d(np.asarray(self.points, dtype=float)))
        if not self.stiffness > 0 or len(self.points) < 3:
            raise MasslineError("a foam support needs a positive stiffness and at least 3 contact points")


def check_support(spec: str, numbers: list[float], loss: float, positive: bool) -> None:
    """Refuse ``--suspension`` ``spec`` unless its ``numbers`` are finite, ``loss`` a finite η ≥ 0 and the
    stiffness and length (or shear ratio) in range (``positive``)."""
    if not (np.isfinite(numbers).all() and np.isfinite(loss) and loss >= 0 and positive):
        raise MasslineError(
            f"{param('suspension', repr(spec), cli=spec)}: give finite numbers, k > 0 N/m, L > 0 m (shear ≥ 0) "
            "and loss ≥ 0"
        )


@dataclass(frozen=True)
class Suspension:
    """Cords and/or a foam pad, their loss factor, and the direction of ``up``.

    ``Suspension()`` (no cord, no foam) is the ideal free body.
    """

    cords: tuple[Cord, ...] = ()
    foam: Foam | None = None
    loss_factor: float = 0.05
    up: np.ndarray = field(default_factory=lambda: UP.copy())

    @property
    def is_free(self) -> bool:
        return not self.cords and self.foam is None

    @classmethod
    def parse(cls, spec: str, mesh, body: RigidBody) -> "Suspension":
        """``--suspension``: 'cord[:k=N/m,L=m,at=X;Y;Z,loss=η]', 'foam[:k=N/m,shear=r,loss=η]' or 'none'.

        Defaults follow Appendix A: a soft (``STRETCH``) long (``CORD_LENGTH``) cord tied to the surface point
        of ``mesh`` straight above the CoG of ``body``; foam under the lowest points with its bounce at
        ``FOAM_BOUNCE``.
        """
        kind, _, rest = spec.partition(":")
        try:
            options = {k.strip(): v.strip() for k, v in (item.split("=", 1) for item in rest.split(",") if item)}
        except ValueError:
            raise MasslineError(f"cannot read suspension options '{rest}': write key=value,key=value") from None
        try:
            loss = float(options.pop("loss", 0.05))
            if kind == "none":
                return cls()
            if kind == "cord":
                at = options.pop("at", None)
                point = point_above(mesh, body.cog)[0] if at is None else np.array(at.split(";"), dtype=float)
                default = Cord.soft(point, body.mass)
                k = float(options.pop("k", default.stiffness))
                length = float(options.pop("L", default.length))
                check_support(spec, [k, length, *point], loss, k > 0 and length > 0)
                suspension = cls(cords=(Cord(point, k, length),), loss_factor=loss)
            elif kind == "foam":
                k = float(options.pop("k", body.mass * (2 * np.pi * FOAM_BOUNCE) ** 2))
                shear = float(options.pop("shear", 0.5))
                check_support(spec, [k, shear], loss, k > 0 and shear >= 0)
                suspension = cls(foam=Foam(lowest_points(mesh, body.cog), k, shear), loss_factor=loss)
            else:
                raise MasslineError(f"unknown suspension '{kind}': use cord, foam or none")
        except MasslineError:
            raise
        except ValueError:
            raise MasslineError(
                f"cannot read {param('suspension', repr(spec), cli=spec)}: numbers are needed (e.g. cord:k=500,L=1)"
            ) from None
        if options:
            raise MasslineError(f"{param('suspension', repr(kind), cli=kind)}: unknown option(s) {', '.join(options)}")
        return suspension

    def as_dict(self) -> dict:
        """The support as plan.json and the truth file keep it: SI, the test frame (``from_dict`` reads it)."""
        cords = [
            {
                "attachment": c.attachment.tolist(),
                "stiffness": c.stiffness,
                "length": c.length,
                "direction": None if c.direction is None else np.asarray(c.direction, dtype=float).tolist(),
            }
            for c in self.cords
        ]
        foam = self.foam and {
            "points": self.foam.points.tolist(),
            "stiffness": self.foam.stiffness,
            "shear_ratio": self.foam.shear_ratio,
        }
        return {"cords": cords, "foam": foam, "loss_factor": self.loss_factor, "up": self.up.tolist()}

    @classmethod
    def from_dict(cls, doc: dict) -> "Suspension":
        """The support ``as_dict`` wrote; MasslineError when a key is missing or not a number."""
        try:
            cords = tuple(
                Cord(c["attachment"], float(c["stiffness"]), float(c["length"]), vector(c.get("direction")))
                for c in doc["cords"]
            )
            foam = doc.get("foam")
            pad = foam and Foam(foam["points"], float(foam["stiffness"]), float(foam.get("shear_ratio", 0.5)))
            return cls(cords, pad or None, float(doc.get("loss_factor", 0.05)), np.asarray(doc.get("up", UP), float))
        except (KeyError, TypeError, ValueError):
            raise MasslineError(
                "plan file: its 'suspension' needs cords (attachment, stiffness, length) or a foam pad (points, "
                "stiffness): write it again with 'massline plan'"
            ) from None

    def describe(self) -> str:
        """'free', 'foam k=… N/m' or 'cord k=… N/m, L=… m at (x, y, z) mm'."""
        if self.is_free:
            return "free"
        if self.foam is not None:
            return f"foam k={self.foam.stiffness:.0f} N/m"
        c = self.cords[0]
        return f"cord k={c.stiffness:.0f} N/m, L={c.length:g} m at {vector_text(np.round(c.attachment * 1e3))} mm"

    def supports(self) -> tuple[np.ndarray, np.ndarray]:
        """Support points (k, 3) and the unit direction (k, 3) in which each one pushes or pulls."""
        points = [c.attachment for c in self.cords]
        directions = [self.up if c.direction is None else c.direction / np.linalg.norm(c.direction) for c in self.cords]
        if self.foam is not None:
            points += list(self.foam.points)
            directions += [self.up] * len(self.foam.points)
        return np.array(points).reshape(-1, 3), np.array(directions).reshape(-1, 3)

    def reactions(self, body: RigidBody) -> np.ndarray:
        """Static support forces (N, one per support) that carry the weight m·g.

        The least-norm solution of the six equilibrium equations: for equal
        foam springs it is the linear-spring solution; for a single cord it
        requires the attachment straight above the CoG, within the MAX_TILT
        the body would settle to (a small tilt leaves the modes unchanged).
        """
        points, directions = self.supports()
        wrenches = np.vstack([directions.T, np.cross(points - body.cog, directions).T])
        weight = np.concatenate([body.mass * GRAVITY * self.up, np.zeros(3)])
        tensions, *_ = np.linalg.lstsq(wrenches, weight, rcond=None)
        lever = np.linalg.norm(points - body.cog, axis=1).max()
        unbalanced = wrenches @ tensions - weight
        tilt = np.linalg.norm(unbalanced[3:]) / (body.mass * GRAVITY * lever)  # sine of the tilt it causes
        if np.linalg.norm(unbalanced[:3]) > 1e-6 * weight[:3] @ self.up or tilt > np.sin(np.radians(MAX_TILT)):
            raise MasslineError(
                "the supports cannot hold the body level: attach a single cord straight above the CoG "
                f"(at x={body.cog[0]:.4g}, y={body.cog[1]:.4g} m) or use several cords around it"
            )
        if np.any(tensions < -1e-9 * body.mass * GRAVITY):
            raise MasslineError("a cord or foam point would have to push or pull the wrong way: move the supports")
        return tensions

    def point_springs(self, body: RigidBody) -> list[tuple[np.ndarray, np.ndarray]]:
        """(point, 3×3 stiffness in N/m) of every elastic support element."""
        springs = []
        tensions = self.reactions(body) if not self.is_free else np.zeros(0)
        for cord, tension in zip(self.cords, tensions):
            direction = self.up if cord.direction is None else cord.direction
            springs.append((cord.attachment, cord_stiffness(direction, cord.stiffness, tension, cord.length)))
        if self.foam is not None:
            k = self.foam.stiffness / len(self.foam.points)
            up = np.outer(self.up, self.up)
            pad = k * up + self.foam.shear_ratio * k * (np.eye(3) - up)
            springs += [(p, pad) for p in self.foam.points]
        return springs

    def geometric_stiffness(self, body: RigidBody) -> np.ndarray:
        """Rotational stiffness (3×3, N·m/rad) of gravity and the support reactions as dead loads."""
        if self.is_free:
            return np.zeros((3, 3))
        points, directions = self.supports()
        K = load_stiffness(-body.mass * GRAVITY * self.up, body.cog)
        for point, direction, reaction in zip(points, directions, self.reactions(body)):
            K = K + load_stiffness(reaction * direction, point)
        return K

    def spring_matrix(self, body: RigidBody) -> np.ndarray:
        """6×6 stiffness about O of the elastic support elements alone, Σ P(a)ᵀ K_a P(a)."""
        K = np.zeros((6, 6))
        for point, k in self.point_springs(body):
            P = point_map(point)
            K += P.T @ k @ P
        return K

    def stiffness_matrix(self, body: RigidBody) -> np.ndarray:
        """Total 6×6 suspension stiffness about O: springs plus gravity's load stiffness."""
        K = self.spring_matrix(body)
        K[3:, 3:] += self.geometric_stiffness(body)
        return K


def hung_over(suspension: Suspension, cog: np.ndarray) -> Suspension:
    """The support with a single cord's pivot moved level until it hangs straight above ``cog`` (m), as a lab
    re-hangs a body whose balance changed (accelerometers on); cords in a group and foam stay."""
    if len(suspension.cords) != 1:
        return suspension
    cord, up = suspension.cords[0], suspension.up
    shift = np.asarray(cog, dtype=float) - cord.attachment
    return replace(suspension, cords=(replace(cord, attachment=cord.attachment + shift - (shift @ up) * up),))


def vector(value) -> np.ndarray | None:
    """A JSON list of three numbers as an array; None stays None."""
    return None if value is None else np.asarray(value, dtype=float).reshape(3)


def single_cord(body: RigidBody, stiffness: float, length: float, height: float, up=UP) -> Suspension:
    """One vertical cord attached ``height`` m straight above the CoG (Appendix A's rig)."""
    up = np.asarray(up, dtype=float)
    return Suspension(cords=(Cord(body.cog + height * up, stiffness, length),), up=up)


def rigid_suspension_modes(body: RigidBody, suspension: Suspension) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (Hz, ascending, 6) and mode shapes (6×6 columns, q at O) of the rigid body
    on its suspension, undamped."""
    K = suspension.stiffness_matrix(body)
    eigenvalues, shapes = eigh(0.5 * (K + K.T), body.mass_matrix)
    return np.sqrt(np.clip(eigenvalues, 0.0, None)) / (2 * np.pi), shapes
