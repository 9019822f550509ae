"""Blind scenarios: a realistic virtual test with one fault concealed, of random size and place.

The clean test is what a careful lab produces: the planned layout hung on a
soft cord (bounce 1 Hz, 1 m, 2 cm above the CoG), the body's elastic modes, 1 %
noise, and every accelerometer reading a few per cent across its axis, as
datasheets allow. A fault is one effect of the diagnosis library drawn from a
realistic range (``RANGES``) at a random place:

* the instrumentation effects of :mod:`.effects` on one line;
* ``suspension``: the body rests on a support much stiffer than planned (its bounce
  at 0.2–0.4 of the planned band's lower edge), attached at a random point;
* ``residual_flexibility``: the body is softer than its mesh says (a joint, a
  different alloy): its elastic modes at 2–4 × the planned band's upper edge.

The planned band is where the ideal massline holds to ``BAND_TOLERANCE`` on the
nominal test, which the engineer passes to the diagnosis (``--band``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from massline.placement.errors import MasslineError
from massline.placement.lines import Lines
from massline.placement.rigid_body import RigidBody
from massline.uff.recording import Recording
from massline.virtual.band import predict_band
from massline.virtual.effects import Effect
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import GRAVITY, UP, Cord, Suspension
from massline.virtual.virtual_test import Acquisition, run

BAND_TOLERANCE = 0.0025  # the planned band: FRFs within 0.25 % of the massline
TRANSVERSE = (0.0, 0.02)  # every channel's transverse sensitivity, drawn uniformly (fraction)
RANGES = {
    "sensor_direction": (8.0, 20.0),  # degrees
    "sensor_gain": (0.05, 0.3),  # fraction, either sign
    "sensor_location": (0.005, 0.02),  # m
    "excitation_direction": (8.0, 20.0),  # degrees
    "excitation_location": (0.005, 0.02),  # m
    "sensor_mass_loading": (0.02, 0.05),  # fraction of the body's mass
    "suspension": (0.2, 0.4),  # bounce / planned band's lower edge
    "residual_flexibility": (2.0, 4.0),  # first elastic mode / planned band's upper edge
    "sensor_polarity": None,
    "channel_swap": None,
}
FAULTS = tuple(RANGES)


@dataclass(frozen=True, eq=False)
class Bench:
    """A body on the bench with its planned layout: what stays fixed across scenarios."""

    body: RigidBody
    sensors: Lines
    exciters: Lines
    modes: object
    fmax: float
    lines: int = 2000

    @property
    def cord(self) -> Suspension:
        """The planned support: bounce 1 Hz on a 1 m cord, 2 cm above the CoG."""
        return Suspension(cords=(Cord(self.body.cog + 0.02 * UP, self.body.mass * GRAVITY / 0.25, 1.0),))

    def planned_band(self) -> tuple[float, float]:
        model = SuspendedBody(self.body, self.modes, self.cord, np.zeros(0), np.zeros((0, 3)), 0.002)
        band = predict_band(model, self.sensors, self.exciters, BAND_TOLERANCE)
        return float(band.low), float(band.high)


def scenario(bench: Bench, fault: str | None, seed: int) -> tuple[Recording, dict]:
    """The recording of one blind test and its truth (``truth["fault"]``: name, size, lines 1-based)."""
    rng = np.random.default_rng(seed)
    for attempt in range(20):
        try:
            return _draw(bench, fault, rng, seed * 100 + attempt)
        except MasslineError:  # a moved sensor or hit that left the solid: draw again
            continue
    raise MasslineError(f"no valid draw of {fault} in 20 attempts")


def _draw(bench: Bench, fault: str | None, rng: np.random.Generator, seed: int) -> tuple[Recording, dict]:
    low, high = bench.planned_band()
    effects = [Effect("transverse_sensitivity", float(rng.uniform(*TRANSVERSE)), "all")]
    cord, modes, size, where = bench.cord, bench.modes, None, None
    n_s, n_e = len(bench.sensors), len(bench.exciters)
    if fault == "suspension":
        size = float(rng.uniform(*RANGES[fault])) * low
        point = bench.body.cog + rng.uniform(0.01, 0.05) * UP  # a single cord must hang above the CoG
        cord = Suspension(cords=(Cord(point, bench.body.mass * (2 * np.pi * size) ** 2, 0.3),))
    elif fault == "residual_flexibility":
        size = float(rng.uniform(*RANGES[fault])) * high
        modes = replace(bench.modes, omega=bench.modes.omega * size / bench.modes.frequencies_hz[0])
    elif fault in ("sensor_polarity", "channel_swap"):
        where = tuple(rng.choice(n_s, size=1 if fault == "sensor_polarity" else 2, replace=False).tolist())
        effects.append(Effect(fault, 0.0, where))
    elif fault is not None:
        size = float(rng.uniform(*RANGES[fault]))
        if fault == "sensor_gain":
            size *= rng.choice([-1.0, 1.0])
        if fault == "sensor_mass_loading":
            size *= bench.body.mass
        where = (int(rng.integers(n_e if fault.startswith("excitation") else n_s)),)
        effects.append(Effect(fault, size, where))
        if fault == "sensor_mass_loading":  # the cord is hung above the loaded body's CoG
            m, p = bench.body.mass, bench.sensors.points[where[0]]
            cog = (m * bench.body.cog + size * p) / (m + size)
            cord = Suspension(cords=(replace(bench.cord.cords[0], attachment=cog + 0.02 * UP),))
    setup = Acquisition(bench.fmax, bench.lines)
    recording, truth = run(bench.body, bench.sensors, bench.exciters, modes, cord, tuple(effects), setup, seed)
    truth["fault"] = {"name": fault, "size": size, "lines": None if where is None else [w + 1 for w in where]}
    truth["planned_band_hz"] = [low, high]
    return recording, truth
