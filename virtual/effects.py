"""Instrumentation effects: what turns the planned layout into the one actually measured.

Each effect is off unless named, with a size, at a place (``NAME=SIZE@WHERE``):

==========================  =========  ================================================
name                        size       what it does to the named line(s)
==========================  =========  ================================================
``sensor_direction``        degrees    accelerometer tilted about an axis ⊥ its own
                                       (a triaxial turns as one block)
``transverse_sensitivity``  fraction   reads s·(a·t) besides a·d, t ⊥ d at random
``sensor_gain``             fraction   reading scaled by (1 + g)
``sensor_polarity``         —          reading sign flipped
``sensor_location``         m          glued δ away from its planned point, δ ⊥ d
``sensor_mass_loading``     kg         a mass at the sensor's point (per accelerometer)
``channel_swap``            —          two channels' labels exchanged (@i,j)
``excitation_direction``    degrees    hammer hit tilted away from the planned direction
``excitation_location``     m          hit δ away from its planned point, δ ⊥ d
==========================  =========  ================================================

WHERE is a 1-based sensor (or exciter) number, several numbers separated by
commas, or ``all``; without it one line is drawn at random. Sensor numbers
count channels (a triaxial accelerometer has three).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.effect_names import DISCRETE, EXCITER_EFFECTS, SIMULATED
from massline.core.errors import MasslineError
from massline.core.lines import Lines

EFFECTS = SIMULATED


@dataclass(frozen=True)
class Effect:
    """One instrumentation effect: its name, size (units in the module table) and lines (0-based)."""

    name: str
    size: float = 0.0
    where: tuple[int, ...] | str | None = None  # indices, "all", or None for one at random

    @classmethod
    def parse(cls, text: str) -> "Effect":
        """``NAME[=SIZE][@WHERE]``, e.g. ``sensor_direction=3@4``, ``transverse_sensitivity=0.03@all``."""
        head, _, where = text.partition("@")
        name, has_size, size = head.partition("=")
        name = name.strip()
        if name not in EFFECTS:
            raise MasslineError(f"unknown effect '{name}': use one of {', '.join(EFFECTS)}")
        if not has_size and name not in DISCRETE:
            raise MasslineError(f"effect {name} needs a size: {name}=SIZE[@WHERE] (see 'massline simulate --help')")
        try:
            value = float(size) if has_size else 0.0
            place = None if not where else "all" if where.strip() == "all" else _indices(where)
        except ValueError:
            raise MasslineError(f"cannot read effect '{text}': write NAME=SIZE@N or NAME=SIZE@all") from None
        if name == "channel_swap" and (not isinstance(place, tuple) or len(place) != 2):
            raise MasslineError("channel_swap needs the two channels: channel_swap@I,J")
        return cls(name, value, place)


@dataclass(frozen=True, eq=False)
class Instrumentation:
    """The layout as actually measured.

    Attributes
    ----------
    sensor_points, sensor_vectors : (n_s, 3) arrays
        Where each accelerometer sits (m) and what it reads per m/s² (axis × gain, with
        transverse sensitivity).
    exciter_points, exciter_vectors : (n_e, 3) arrays
        Where each hit lands (m) and its unit force direction.
    masses, mass_points : (k,) and (k, 3) arrays
        Point masses added to the body (kg, m).
    channel_order : (n_s,) int array
        Recorded channel c holds the signal of sensor ``channel_order[c]``.
    applied : list of dict
        Every effect as drawn: name, size, lines (1-based), and the perpendicular chosen.
    """

    sensor_points: np.ndarray
    sensor_vectors: np.ndarray
    exciter_points: np.ndarray
    exciter_vectors: np.ndarray
    masses: np.ndarray
    mass_points: np.ndarray
    channel_order: np.ndarray
    applied: list = field(default_factory=list)


def _indices(where: str) -> tuple[int, ...]:
    """'3,5' → (2, 4): 1-based numbers on the command line, 0-based indices inside."""
    return tuple(int(w) - 1 for w in where.split(","))


def perpendicular(d: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A random unit vector ⊥ d."""
    v = rng.normal(size=3)
    v -= (v @ d) * d
    return v / np.linalg.norm(v)


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation matrix about unit ``axis`` by ``angle`` rad."""
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def check_targets(effects: list[Effect], n_sensors: int, n_exciters: int) -> None:
    """Raise a MasslineError for an effect placed on a sensor or exciter the plan does not have."""
    for effect in effects:
        n = n_exciters if effect.name in EXCITER_EFFECTS else n_sensors
        if isinstance(effect.where, tuple) and any(not 0 <= t < n for t in effect.where):
            what = "exciter" if effect.name in EXCITER_EFFECTS else "sensor"
            raise MasslineError(f"effect {effect.name}: there is no {what} {max(effect.where) + 1} (the plan has {n})")


def _targets(effect: Effect, lines: Lines, rng: np.random.Generator) -> list[int]:
    n = len(lines)
    if effect.where == "all":
        return list(range(n))
    return [int(rng.integers(n))] if effect.where is None else list(effect.where)


def _block(lines: Lines, i: int) -> list[int]:
    """Line i and the other axes of its triaxial accelerometer."""
    group = lines.triaxial[i]
    return [i] if group < 0 else list(np.flatnonzero(lines.triaxial == group))


def instrument(sensors: Lines, exciters: Lines, effects: list[Effect], rng: np.random.Generator) -> Instrumentation:
    """Apply ``effects`` to the planned lines, drawing random places and perpendiculars from ``rng``."""
    check_targets(effects, len(sensors), len(exciters))
    s_pts, s_vec = sensors.points.copy(), sensors.directions.copy()
    e_pts, e_vec = exciters.points.copy(), exciters.directions.copy()
    masses, mass_points, order, applied = [], [], np.arange(len(sensors)), []
    for effect in effects:
        lines = exciters if effect.name in EXCITER_EFFECTS else sensors
        targets = _targets(effect, lines, rng)
        record = {"effect": effect.name, "size": effect.size, "lines": [t + 1 for t in targets]}
        done = set()
        for t in targets:
            block = _block(lines, t)
            d = lines.directions[t]
            if effect.name == "sensor_direction" and t not in done:
                axis = perpendicular(d, rng)
                s_vec[block] = s_vec[block] @ rotation(axis, np.radians(effect.size)).T
                record.setdefault("axes", []).append(axis.tolist())
            elif effect.name == "transverse_sensitivity":
                t_dir = perpendicular(d, rng)
                s_vec[t] += effect.size * t_dir
                record.setdefault("transverse", []).append(t_dir.tolist())
            elif effect.name == "sensor_gain":
                s_vec[t] *= 1 + effect.size
            elif effect.name == "sensor_polarity":
                s_vec[t] *= -1
            elif effect.name == "sensor_location" and t not in done:
                offset = effect.size * perpendicular(d, rng)
                s_pts[block] += offset
                record.setdefault("offsets", []).append(offset.tolist())
            elif effect.name == "sensor_mass_loading" and t not in done:
                masses.append(effect.size)
                mass_points.append(s_pts[t].copy())
            elif effect.name == "excitation_direction":
                e_vec[t] = rotation(perpendicular(d, rng), np.radians(effect.size)) @ e_vec[t]
                record.setdefault("directions", []).append(e_vec[t].tolist())
            elif effect.name == "excitation_location":
                offset = effect.size * perpendicular(d, rng)
                e_pts[t] += offset
                record.setdefault("offsets", []).append(offset.tolist())
            done.update(block)
        if effect.name == "channel_swap":
            i, j = targets
            order[[i, j]] = order[[j, i]]
        applied.append(record)
    return Instrumentation(
        s_pts,
        s_vec,
        e_pts,
        e_vec,
        np.array(masses, dtype=float),
        np.array(mass_points, dtype=float).reshape(-1, 3),
        order,
        applied,
    )
