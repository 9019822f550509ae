"""One virtual test: the planned layout, as instrumented, on the suspended elastic body, recorded.

``run`` ties the pieces together and returns the ``Recording`` a test system
would store together with the truth: everything that was simulated, including
what the recording conceals (effects, suspension, elastic modes, the body that
was actually on the suspension with its sensor masses).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from massline.core.calibration import Calibration
from massline.core.effect_names import SimulatedEffect
from massline.core.housing_masses import HousingMasses
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.core.numbering import point_groups
from massline.core.rigid_body import RigidBody
from massline.uff.recording import Recording
from massline.virtual.analyser import impact_setup
from massline.virtual.band_prediction import predict_band
from massline.virtual.chain_errors import draw_chain_errors
from massline.virtual.effects import Instrumentation, instrument
from massline.virtual.hum import channel_levels, check_hum, with_hum
from massline.virtual.measurement import ImpactTest, Noise, impact_test, noisy_frfs, with_dc_line
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension, hung_over

LINES = 2000  # the direct route's spectral lines


@dataclass(frozen=True)
class Acquisition:
    """How the test is run and recorded.

    Attributes
    ----------
    fmax : float or None
        Analysis bandwidth, Hz; None: on the direct route 1.5 × the first elastic mode (or 40 × the top
        suspension mode for a rigid model), so the recording shows zones A, B and the start of C; on the impact
        route what a test engineer sets up around the predicted band (:mod:`.analyser`).
    lines : int or None
        Spectral lines (Δf = fmax / lines); the recording holds lines + 1 values with the DC line. None: 2000 on
        the direct route; on the impact route enough for the lowest support mode (:mod:`.analyser`).
    noise : Noise
        FRF noise of the direct route (ignored by the impact route, which has its own).
    impact : ImpactTest or None
        Simulate hammer hits and H1 averaging instead of adding noise to exact FRFs (its pulse None: the
        hammer tip :mod:`.analyser` chooses).
    sensor_mass : float or HousingMasses
        Mass of every accelerometer (kg), or per point label, added at its point (a triaxial counts once).
    modal_loss : float
        Loss factor of the elastic modes.
    dc_line : bool
        Start the recording at 0 Hz, as exporters store lines + DC: a real-valued outlier with a low
        coherence (noise and window residue, no massline), which identify sets aside.
    chain : Calibration or None
        The measuring chain's 1-σ its errors are drawn from (:mod:`.chain_errors`: each accelerometer's and the
        force transducer's calibration, each channel's transverse sensitivity); None: an ideal chain.
    """

    fmax: float | None = None
    lines: int | None = None
    noise: Noise = field(default_factory=Noise)
    impact: ImpactTest | None = None
    sensor_mass: float | HousingMasses = 0.0
    modal_loss: float = 0.002
    dc_line: bool = True
    chain: Calibration | None = None


def accelerometer_masses(sensors: Lines, mass: float | HousingMasses) -> tuple[np.ndarray, np.ndarray]:
    """One mass per physical accelerometer (a point of :mod:`massline.core.numbering`: a triaxial counts once),
    ``mass`` kg each or per point label: masses (k,), points (k, 3) of those weighing more than 0."""
    masses = mass if isinstance(mass, HousingMasses) else HousingMasses(float(mass))
    group = point_groups(sensors)
    labels, first = np.unique(group, return_index=True)
    masses.check_labels(labels + 1)
    each = masses.of(labels + 1)
    return each[each > 0], sensors.points[first[each > 0]]


def sensor_mass_payload(mass: float | HousingMasses) -> float | dict:
    """The truth file's ``sensor_mass``: kg per housing, or {"default": kg, "by_point": {label: kg}}."""
    if not isinstance(mass, HousingMasses):
        return float(mass)
    if not mass.by_label:
        return mass.default
    return {"default": mass.default, "by_point": {str(k): v for k, v in mass.by_label.items()}}


def on_the_body(modes, planned: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """Points (n, 3) m an effect moved off the solid brought to its nearest point (a sensor slid 8 mm past an edge
    sits on the body, as a hit that misses its mark still lands on it); the others as they are. Without the FE
    model (``modes`` None, or one that cannot say), as moved."""
    nearest = getattr(modes, "nearest", None)
    changed = np.any(moved != planned, axis=1)
    if nearest is None or not changed.any():
        return moved
    out = moved.copy()
    out[changed] = nearest(moved[changed])
    return out


def auto_fmax(model: SuspendedBody) -> float:
    """The direct route's bandwidth, Hz: 1.5 × the first elastic mode, or 40 × the top support mode if rigid."""
    if model.n_elastic:
        return 1.5 * model.first_elastic_frequency
    return 40.0 * max(model.suspension_frequencies.max(), 1.0)


def run(
    body: RigidBody,
    sensors: Lines,
    exciters: Lines,
    modes=None,
    suspension: Suspension | None = None,
    effects: tuple[SimulatedEffect, ...] = (),
    setup: Acquisition | None = None,
    seed: int = 0,
) -> tuple[Recording, dict]:
    """Simulate the test; return the recording and the truth (a JSON-ready dict).

    ``effects``: the instrumentation effects concealed, objects of the registry
    (:mod:`massline.identify.diagnose.effects`, e.g. ``parse_effect("sensor_gain=0.1@3")``), applied in order.
    """
    setup = setup or Acquisition()
    suspension = suspension or Suspension()
    rng = np.random.default_rng(seed)
    inst = instrument(sensors, exciters, list(effects), rng)
    inst.sensor_points = on_the_body(modes, sensors.points, inst.sensor_points)
    inst.exciter_points = on_the_body(modes, exciters.points, inst.exciter_points)
    chain = None if setup.chain is None else draw_chain_errors(setup.chain, sensors.directions, seed)
    if chain is not None:
        inst.sensor_vectors, inst.force_gain = chain.reading_vectors(inst.sensor_vectors), chain.force_gain
    placed = Lines(inst.sensor_points, sensors.directions, sensors.triaxial)
    masses, points = accelerometer_masses(placed, setup.sensor_mass)
    masses, points = np.concatenate([masses, inst.masses]), np.vstack([points, inst.mass_points])
    loaded = SuspendedBody(body, None, Suspension(), masses, points).loaded
    hung = hung_over(suspension, loaded.cog)  # re-hung level, as a lab does when a concealed mass tips the body
    model = SuspendedBody(body, modes, hung, masses, points, setup.modal_loss)
    band = predict_band(model, sensors, exciters)
    analyser = None
    if setup.impact is not None:
        impact = setup.impact
        given = (setup.fmax, setup.lines, impact.pulse)
        analyser = impact_setup(band, model.suspension_frequencies, impact.window_end, *given, record=impact.record)
        setup = replace(setup, fmax=analyser.fmax, lines=analyser.lines, impact=replace(impact, pulse=analyser.pulse))
    setup = replace(setup, fmax=setup.fmax or auto_fmax(model), lines=setup.lines or LINES)
    check_hum(inst.hums, setup.fmax / setup.lines * np.arange(1, setup.lines + 1))
    masslines = synthesise(model.loaded, sensors, exciters).values
    frequencies, frf, coherence = measure(model, inst, setup, (body.mass, masslines), rng)
    windowed = setup.impact is not None  # an impact test's exponential window, as its file's 1858 says
    averaged = f", H1 of {setup.impact.averages} averages" if windowed else ""  # what the header says of the hits
    recording = Recording(
        frequencies, frf, sensors, exciters, coherence, "massline virtual test" + averaged, exponential_window=windowed
    )
    truth = {
        "seed": seed,
        "nominal": body.as_dict(),
        "loaded": model.loaded.as_dict(),
        "effects": inst.applied,
        "chain": None if chain is None else chain.payload,
        "sensor_mass": sensor_mass_payload(setup.sensor_mass),
        "added_masses": {"mass": model.masses.tolist(), "points": model.mass_points.tolist()},
        "exciter_masses": inst.exciter_masses.tolist(),
        "suspension": suspension_summary(suspension, model),
        "elastic_hz": [] if modes is None else (np.asarray(modes.omega) / (2 * np.pi)).tolist(),
        "natural_hz": model.natural_frequencies.tolist(),
        "band_hz": [band.low, band.high],
        "noise": None if setup.impact else {"relative": setup.noise.relative, "floor": setup.noise.floor},
        "impact": None if setup.impact is None else vars(setup.impact),
        "fmax_hz": setup.fmax,
        "lines": setup.lines,
        "record_s": setup.lines / setup.fmax,
        "dc_line": setup.dc_line,
        "warnings": [] if analyser is None else list(analyser.warnings),
        "instrumented": {
            "sensor_points": inst.sensor_points.tolist(),
            "sensor_vectors": inst.sensor_vectors.tolist(),
            "exciter_points": inst.exciter_points.tolist(),
            "exciter_vectors": inst.exciter_vectors.tolist(),
            "channel_order": inst.channel_order.tolist(),
        },
    }
    return recording, truth


def driven_bodies(model: SuspendedBody, inst: Instrumentation) -> list[SuspendedBody]:
    """The body each exciter drives: ``model`` with the mass riding at that exciter's point (a force gauge's
    structure side), one per column."""
    return [model.carrying(m, p) for m, p in zip(inst.exciter_masses, inst.exciter_points)]


def measure(
    model: SuspendedBody, inst: Instrumentation, setup: Acquisition, scale: tuple, rng: np.random.Generator
):
    """Frequencies (Hz), FRFs ((m/s²)/N) and coherence as the test system stores them, by either route; column j
    measured on the body exciter j drives (:func:`driven_bodies`).

    ``scale``: the body's mass (kg), the noise floor's scale (1/mass), and the loaded rigid body's masslines
    (n_s, n_e) (m/s²)/N, the mains hum's (each channel's level). The hum is drawn from a generator spawned from
    ``rng``: the noise is the same with or without it.
    """
    bodies = driven_bodies(model, inst)

    def accelerance(f):
        if not inst.exciter_masses.any():
            H = model.accelerance(f, inst.sensor_points, inst.sensor_vectors, inst.exciter_points, inst.exciter_vectors)
            return inst.read_through(H, f)[inst.channel_order]
        columns = [
            body.accelerance(f, inst.sensor_points, inst.sensor_vectors, p[None], v[None])
            for body, p, v in zip(bodies, inst.exciter_points, inst.exciter_vectors)
        ]
        return inst.read_through(np.concatenate(columns, axis=1), f)[inst.channel_order]

    n_s, n_e = len(inst.sensor_vectors), len(inst.exciter_vectors)
    mass, masslines = scale
    levels = channel_levels(masslines)
    if setup.impact is not None:
        given = (setup.fmax, setup.lines, setup.impact, rng)
        return impact_test(accelerance, n_s, n_e, *given, dc=setup.dc_line, hums=tuple(inst.hums), levels=levels)
    frequencies = setup.fmax / setup.lines * np.arange(1, setup.lines + 1)
    frf, coherence = noisy_frfs(accelerance(frequencies), setup.noise, mass, rng)
    frf, coherence = with_hum(frequencies, frf, coherence, inst.hums, masslines, rng.spawn(1)[0])
    if setup.dc_line:
        return with_dc_line(frequencies, frf, coherence, rng)
    return frequencies, frf, coherence


def suspension_summary(suspension: Suspension, model: SuspendedBody) -> dict:
    """The support as simulated, for the truth file."""
    tensions = [] if suspension.is_free else model.suspension.reactions(model.loaded).tolist()
    return suspension.as_dict() | {
        "reactions": tensions,
        "modes_hz": model.suspension_frequencies.tolist(),
    }
