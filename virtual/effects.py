"""Instrumentation effects applied: what turns the planned layout into the one actually measured.

The effects themselves (what each changes, its size's unit, its ``--effect`` syntax) are classes of the
registry, :mod:`massline.identify.diagnose.effects`, which this layer cannot import (DESIGN.md): callers
(``massline simulate``, the demo, the blind scenarios, tests) build the effect objects there and pass them
in. Here is the generic machinery: the :class:`Instrumentation` being built and the loop that hands it to
each effect's ``simulate`` hook (:class:`massline.core.effect_names.SimulatedEffect`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.effect_names import SimulatedEffect
from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.virtual.hum import Hum, check_fundamental


@dataclass(eq=False)
class Instrumentation:
    """The layout as actually measured (built by :func:`instrument`, each effect changing it in place).

    Attributes
    ----------
    sensor_points, sensor_vectors : (n_s, 3) arrays
        Where each accelerometer sits (m) and what it reads per m/s² (axis × gain, with
        transverse sensitivity).
    exciter_points, exciter_vectors : (n_e, 3) arrays
        Where each hit lands (m) and its unit force direction.
    masses, mass_points : (k,) and (k, 3) arrays
        Point masses added to the body (kg, m).
    exciter_masses : (n_e,) array
        Mass (kg) riding on the body at each exciter's point while that exciter drives it, and only then: a
        force gauge's structure side (a shaker moved between runs; each column of the FRF matrix its own body).
    channel_order : (n_s,) int array
        Recorded channel c holds the signal of sensor ``channel_order[c]``.
    hums : list of Hum
        Mains hum on the response channels (:mod:`massline.virtual.hum`), added as the test is recorded.
    responses : list of (int, callable)
        What a sensor's chain does to its reading in frequency: (sensor, F) with F(f Hz) → complex factor (a
        front end's delay, a mount's resonance), applied to every FRF of that sensor as the test is recorded.
    applied : list of dict
        Every effect as drawn: name, size, lines (1-based), and the perpendicular chosen.
    force_gain : float
        The force transducer's reading per unit of the truth (:mod:`.chain_errors`): every FRF divided by it.
    """

    sensor_points: np.ndarray
    sensor_vectors: np.ndarray
    exciter_points: np.ndarray
    exciter_vectors: np.ndarray
    masses: np.ndarray
    mass_points: np.ndarray
    exciter_masses: np.ndarray
    channel_order: np.ndarray
    hums: list = field(default_factory=list)
    responses: list = field(default_factory=list)
    applied: list = field(default_factory=list)
    force_gain: float = 1.0

    @classmethod
    def planned(cls, sensors: Lines, exciters: Lines) -> "Instrumentation":
        """The layout as planned: every line as labelled, no added mass, channels in order."""
        return cls(
            sensor_points=sensors.points.copy(),
            sensor_vectors=sensors.directions.copy(),
            exciter_points=exciters.points.copy(),
            exciter_vectors=exciters.directions.copy(),
            masses=np.zeros(0),
            mass_points=np.zeros((0, 3)),
            exciter_masses=np.zeros(len(exciters)),
            channel_order=np.arange(len(sensors)),
        )

    def add_hum(self, fundamental: float, level: float) -> None:
        """Mains hum at ``fundamental`` Hz and its harmonics on every response channel, the fundamental's line at
        ``level`` × each channel's massline level (:class:`massline.virtual.hum.Hum`)."""
        self.hums.append(Hum(fundamental, level))

    def add_response(self, sensor: int, factor) -> None:
        """Sensor ``sensor`` (0-based) read through ``factor``: f (Hz, array) → its complex factor on every FRF."""
        self.responses.append((sensor, factor))

    def read_through(self, H: np.ndarray, frequencies: np.ndarray) -> np.ndarray:
        """H (n_s, n_e, n_f) as the chains read it: each row times its responses' factors at ``frequencies`` (Hz),
        over the force transducer's gain."""
        if not self.responses and self.force_gain == 1.0:
            return H
        H = H / self.force_gain
        for sensor, factor in self.responses:
            H[sensor] *= factor(np.asarray(frequencies, dtype=float))
        return H

    def add_mass(self, mass: float, point: np.ndarray) -> None:
        """A point mass (kg) added to the body at ``point`` (m)."""
        self.masses = np.append(self.masses, mass)
        self.mass_points = np.vstack([self.mass_points, point])


def check_targets(
    effects: list[SimulatedEffect], n_sensors: int, n_exciters: int, fmax: float | None = None, lines: int | None = None
) -> None:
    """Raise a MasslineError for an effect placed on a sensor or exciter the plan does not have, or at a frequency
    outside the recorded band Δf–``fmax`` (Hz, Δf = fmax/``lines``; unchecked while ``fmax`` is not known)."""
    for effect in effects:
        if effect.place == "frequency" and fmax is not None:
            check_fundamental(float(effect.where), fmax / lines if lines else 0.0, fmax)
        n = n_exciters if effect.perturbs == "exciter" else n_sensors
        if isinstance(effect.where, tuple) and any(not 0 <= t < n for t in effect.where):
            raise MasslineError(
                f"effect {effect.name}: there is no {effect.perturbs} {max(effect.where) + 1} (the plan has {n})"
            )


def targets_of(effect: SimulatedEffect, lines: Lines, rng: np.random.Generator) -> list[int]:
    """The lines an effect sits on: its ``where``, every line (also when ``where`` is a frequency, not lines),
    or one drawn from ``rng``."""
    n = len(lines)
    if effect.where == "all" or effect.place != "lines":
        return list(range(n))
    return [int(rng.integers(n))] if effect.where is None else list(effect.where)


def instrument(
    sensors: Lines, exciters: Lines, effects: list[SimulatedEffect], rng: np.random.Generator
) -> Instrumentation:
    """Apply ``effects`` to the planned lines in order, drawing random places and perpendiculars from ``rng``."""
    check_targets(effects, len(sensors), len(exciters))
    state = Instrumentation.planned(sensors, exciters)
    for effect in effects:
        lines = exciters if effect.perturbs == "exciter" else sensors
        targets = targets_of(effect, lines, rng)
        record = {"effect": effect.name, "size": effect.size, "lines": [t + 1 for t in targets]}
        record.update(effect.simulate(state, lines, targets, rng))
        state.applied.append(record)
    return state
