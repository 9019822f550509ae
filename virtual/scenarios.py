"""Blind scenarios: a realistic virtual test with its faults concealed, of random size and place.

The clean test is what a careful lab produces: the planned layout on a support (``SUPPORTS``: the
planned soft cord, bounce 1 Hz, 1 m, 2 cm above the CoG; a stiff cord whose top support mode is a
tenth of the first elastic mode; foam pads under the lowest points), the body's elastic modes,
1 % noise, and every accelerometer reading a few per cent across its axis, as datasheets allow.
The file is written as a test system exports it (``STYLES``). A fault is one effect of the
registry (:mod:`massline.identify.diagnose.effects`, handed in as ``effects``: this layer cannot import it)
drawn from its realistic range (its ``blind_range``) at a random place:

* an instrumentation effect on one line (two for a swap);
* ``every_sensor_mass``: every accelerometer housing weighs 5–30 g (capped at ``LOADING_CAP`` of
  the body's mass in all), the tool being given the bare mesh body;
* ``suspension``: the body rests on a support much stiffer than planned (its bounce
  at 0.2–0.4 of the planned band's lower edge, :func:`placing_band`), attached at a random point;
* ``residual_flexibility``: the body is softer than its mesh says (a joint, a
  different alloy): its elastic modes at 2–4 × the planned band's upper edge.

A scenario may carry two faults at once (``PAIRS``), at different accelerometers.
The planned band is the plan's (``Bench.band``, on the plan's support ``Bench.support``), or where every
FRF of the nominal test on the clean support holds to its massline (:func:`.band.predict_band`); the engineer
passes it to the diagnosis (``--band``); where none holds (a plate on foam), none is passed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.uff.recording import Recording
from massline.uff.writer import write_uff
from massline.virtual.attachment import UP, point_above
from massline.virtual.band_prediction import predict_band
from massline.virtual.measurement import ImpactTest
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import GRAVITY, Cord, Suspension, hung_over
from massline.virtual.acquisition import Acquisition, accelerometer_masses, run

TRANSVERSE = (0.0, 0.02)  # every channel's transverse sensitivity, drawn uniformly (fraction)
LOADING_CAP = 0.2  # every housing's mass together: at most this share of the body's mass
EVERY_HOUSING = (0.005, 0.030)  # kg per housing: the ``every_sensor_mass`` scenario
FAULTS = (
    "sensor_direction",
    "sensor_gain",
    "sensor_location",
    "excitation_direction",
    "excitation_location",
    "sensor_mass_loading",
    "every_sensor_mass",
    "suspension",
    "residual_flexibility",
    "sensor_polarity",
    "channel_swap",
)
"""The blind cases: the registry's effects a blind test conceals (each of its own realistic size,
``blind_range``) and ``every_sensor_mass`` (every housing loaded: a scenario, not an effect)."""
PLANAR_FAULTS = (
    "sensor_polarity",
    "channel_swap",
    "sensor_gain",
    "sensor_location",
    "sensor_mass_loading",
    "every_sensor_mass",
)
PAIRS = (
    ("channel_swap", "every_sensor_mass"),
    ("sensor_polarity", "sensor_direction"),
    ("excitation_direction", "suspension"),
)
SUPPORTS = ("soft", "stiff", "foam")
STYLES = ("direct", "exporter", "impact")  # SI file; g/N and mm; hammer hits with H1 over 5 averages


@dataclass(frozen=True, eq=False)
class Bench:
    """A body on the bench with its planned layout: what stays fixed across scenarios.

    ``surface`` is the body's mesh (the foam's pads and the stiff cord's point); ``planar``: a plate;
    ``support`` and ``band`` (Hz) the plan's soft support and its band (None: the soft cord of
    :func:`soft_cord` and the band predicted here).
    """

    body: RigidBody
    sensors: Lines
    exciters: Lines
    modes: object
    fmax: float
    lines: int = 2000
    surface: object = None
    planar: bool = False
    support: Suspension | None = None
    band: tuple[float, float] | None = None

    @property
    def cord(self) -> Suspension:
        """The planned support: the plan's, or bounce 1 Hz on a 1 m cord, 2 cm above the CoG."""
        return self.support or soft_cord(self.body.mass, self.body.cog)

    def planned_band(self, kind: str = "soft") -> tuple[float, float]:
        """The band planned (Hz) on the clean support of ``kind`` for the nominal body: the plan's on the soft
        support when the bench has one, else where every FRF holds to its massline (:func:`.predict_band`)."""
        if kind == "soft" and self.band is not None:
            return self.band
        model = SuspendedBody(self.body, self.modes, support(self, kind, np.zeros(0), np.zeros((0, 3))))
        band = predict_band(model, self.sensors, self.exciters)
        return float(band.low), float(min(band.high, self.fmax))  # a rigid model's band runs to the record's end

    def faults(self) -> tuple:
        """The faults this bench's layout can show (a plate's out-of-plane lines: polarity, swap, gain, location)."""
        return PLANAR_FAULTS if self.planar else FAULTS


@dataclass(frozen=True)
class Conditions:
    """How the test is run and exported: the support (``SUPPORTS``) and the file (``STYLES``)."""

    support: str = "soft"
    style: str = "direct"


def soft_cord(mass: float, cog: np.ndarray) -> Suspension:
    """Bounce 1 Hz on a 1 m cord, 2 cm above ``cog`` (m) of a body of ``mass`` (kg)."""
    return Suspension(cords=(Cord(cog + 0.02 * UP, mass * GRAVITY / 0.25, 1.0),))


def stiff_cord(bench: Bench, masses: np.ndarray, points: np.ndarray) -> Suspension:
    """A 0.3 m cord above the CoG (with the added masses, kg at m) whose top support mode is at a tenth of the
    first elastic mode."""
    m = bench.body.mass + masses.sum()
    cog = (bench.body.mass * bench.body.cog + masses @ points) / m
    point, target = point_above(bench.surface, cog)[0], bench.modes.frequencies_hz[0] / 10

    def top(k: float) -> float:
        cord = Suspension(cords=(Cord(point, k, 0.3),), loss_factor=0.05)
        model = SuspendedBody(bench.body, None, cord, masses, points)
        return model.suspension_frequencies.max() - target

    return Suspension(cords=(Cord(point, brentq(top, 1.0, 1e9), 0.3),), loss_factor=0.05)


def support(bench: Bench, kind: str, masses: np.ndarray, points: np.ndarray) -> Suspension:
    """The clean support of ``kind``; the soft cord is hung above the CoG with the added masses (kg at m)."""
    if kind == "stiff":
        return stiff_cord(bench, masses, points)
    if kind == "foam":
        return Suspension.parse("foam", bench.surface, bench.body)
    m = bench.body.mass + masses.sum()
    cog = (bench.body.mass * bench.body.cog + masses @ points) / m
    return hung_over(bench.support, cog) if bench.support else soft_cord(m, cog)


def scenario(
    bench: Bench, faults, seed: int, conditions: Conditions = Conditions(), *, effects: Mapping
) -> tuple[Recording, dict]:
    """The recording of one blind test and its truth.

    ``faults``: None, a fault's name or a tuple of names (``FAULTS``). ``effects``: the effect classes by name
    (the registry's ``BY_NAME``), which say how each fault is drawn and simulated. ``truth["faults"]``: each
    one's name, size and lines (1-based); ``truth["conditions"]``: the support and the file style.
    """
    names = () if faults is None else (faults,) if isinstance(faults, str) else tuple(faults)
    rng = np.random.default_rng(seed)
    for attempt in range(20):
        try:
            return _draw(bench, names, rng, seed * 100 + attempt, conditions, effects)
        except MasslineError:  # a moved sensor or hit that left the solid: draw again
            continue
    raise MasslineError(f"no valid draw of {names} in 20 attempts")


def _free_lines(bench: Bench, taken: list, count: int, rng: np.random.Generator) -> tuple:
    """``count`` sensor lines at accelerometers no other fault of the scenario uses."""
    points = bench.sensors.points
    free = [i for i in range(len(points)) if all(np.linalg.norm(points[i] - points[t]) > 1e-3 for t in taken)]
    where = tuple(int(i) for i in rng.choice(free, size=count, replace=False))
    taken.extend(where)
    return where


def _fault(bench: Bench, kind, rng: np.random.Generator, taken: list, band) -> tuple[dict, dict]:
    """One fault drawn (``kind``: an effect class of the registry): its truth (size, 0-based lines) and what it
    changes in the test; a support or elastic fault sized against ``band`` (:func:`placing_band`)."""
    if kind.perturbs == "support":
        size = kind.blind_size(rng, bench.body.mass, band)
        point = bench.body.cog + rng.uniform(0.01, 0.05) * UP  # a single cord must hang above the CoG
        return {"size": size, "where": None}, {
            "cord": Suspension(cords=(Cord(point, bench.body.mass * (2 * np.pi * size) ** 2, 0.3),))
        }
    if kind.perturbs == "modes":
        size = kind.blind_size(rng, bench.body.mass, band)
        modes = replace(bench.modes, omega=bench.modes.omega * size / bench.modes.frequencies_hz[0])
        return {"size": size, "where": None}, {"modes": modes}
    if kind.discrete:
        where = _free_lines(bench, taken, kind.lines_needed, rng)
        return {"size": None, "where": where}, {"effect": kind(0.0, where)}
    size = kind.blind_size(rng, bench.body.mass, band)
    if kind.perturbs == "exciter":
        where = (int(rng.integers(len(bench.exciters))),)
    else:
        where = _free_lines(bench, taken, kind.lines_needed, rng)
    return {"size": size, "where": where}, {"effect": kind(size, where)}


def every_housing(bench: Bench, rng: np.random.Generator) -> float:
    """The ``every_sensor_mass`` scenario's mass per housing (kg), capped at ``LOADING_CAP`` of the body in all."""
    count = len(accelerometer_masses(bench.sensors, 1.0)[0])
    cap = min(1.0, LOADING_CAP * bench.body.mass / (count * EVERY_HOUSING[1]))
    return float(rng.uniform(*EVERY_HOUSING)) * cap


def placing_band(bench: Bench, band: tuple) -> tuple[float, float]:
    """The band (Hz) a support or elastic fault is placed against: the test's planned band, the soft support's
    where the test's support plans none (foam, stiff), or where no FRF run holds at all, 3 × the soft support's
    top mode to f1 / 3 (the massline's room between them)."""
    if np.isfinite(band).all():
        return band
    soft = bench.planned_band("soft")
    if np.isfinite(soft).all():
        return soft
    model = SuspendedBody(bench.body, bench.modes, support(bench, "soft", np.zeros(0), np.zeros((0, 3))))
    return 3 * float(model.suspension_frequencies.max()), float(bench.modes.frequencies_hz[0]) / 3


def _draw(bench: Bench, names: tuple, rng: np.random.Generator, seed: int, conditions: Conditions, effects):
    band = bench.planned_band(conditions.support)
    placing = placing_band(bench, band)
    concealed = [effects["transverse_sensitivity"](float(rng.uniform(*TRANSVERSE)), "all")]
    taken, drawn, changes, housing = [], [], {}, 0.0
    masses, points = [], []
    for name in names:
        if name == "every_sensor_mass":  # a scenario, not an effect: the housings' mass (Acquisition.sensor_mass)
            housing = every_housing(bench, rng)
            drawn.append({"name": name, "size": housing, "lines": None})
            continue
        kind = effects[name]
        truth, change = _fault(bench, kind, rng, taken, placing)
        lines = None if truth["where"] is None else [w + 1 for w in truth["where"]]
        drawn.append({"name": name, "size": truth["size"], "lines": lines})
        concealed += [change.pop("effect")] if "effect" in change else []
        changes.update(change)
        if kind.adds_mass:  # the cord is hung above the loaded body's CoG
            masses.append(truth["size"])
            points.append(bench.sensors.points[lines[0] - 1])
    housed, at = accelerometer_masses(bench.sensors, housing)
    masses, points = np.append(housed, masses), np.vstack([at, *points]) if points else at
    cord = changes.get("cord") or support(bench, conditions.support, masses, points)
    setup = acquisition(bench, conditions, housing)
    modes = changes.get("modes", bench.modes)
    recording, truth = run(bench.body, bench.sensors, bench.exciters, modes, cord, tuple(concealed), setup, seed)
    truth["faults"] = drawn
    truth["conditions"] = {"support": conditions.support, "style": conditions.style}
    truth["planned_band_hz"] = list(band) if np.isfinite(band).all() else None  # no band holds: none given
    return recording, truth


def acquisition(bench: Bench, conditions: Conditions, housing: float) -> Acquisition:
    """The direct route on the bench's record (0 Hz line and coherence; on the stiff cord to 1.5 × the first
    elastic mode, past its support modes), or hammer hits with H1 over 5 averages; ``housing``: kg each."""
    if conditions.style == "impact":
        return Acquisition(impact=ImpactTest(averages=5), sensor_mass=housing)
    fmax = None if conditions.support == "stiff" else bench.fmax
    return Acquisition(fmax, bench.lines, sensor_mass=housing)


def write_case(path: Path, recording: Recording, conditions: Conditions) -> None:
    """The Universal File as its style writes it: SI (direct), or mm geometry and g/N (exporter, impact)."""
    if conditions.style == "direct":
        write_uff(path, recording, force=True)
    else:
        write_uff(path, recording, force=True, units="MM", acceleration="g")
