"""The support's action on the body, modelled with the mesh's FE model and taken off the FRFs (stiff cords, foam).

On a stiff support the band is squeezed between the support's top mode and the first elastic mode, and the
support acts through the body's static flexibility too: every FRF departs from its massline by δ_ij(f; θ), of
the order of the massline itself near the band's edges, and a massline fit that reads the departure as tails
(:mod:`.massline_fit`) is off by per cents. With a model of the support and of the elastic modes (``model``:
:class:`massline.virtual.support_model.SupportModel`, built from the mesh and the support's description), the
departure is computed for the body θ identified so far and taken off the recording, and θ is identified again
on H − δ(θ), until it stops moving: a fixed point, where H − δ(θ) has the masslines of θ.

What the description leaves uncertain is fitted to the record before each step: the springs' stiffness (one
scale on every spring) by the FRFs up to just above the support's top resonance, the elastic modes' frequencies
(one scale, √ of Young's modulus over the one assumed) by the FRFs around the first elastic resonance, each
where the record resolves that resonance (:func:`record_resonances`), else left as described. The iteration
begins from the mesh's body and halves its step once steps grow (near the support's modes the correction can
move more than the body, and the plain map overshoots); the lines where an FRF follows the springs more than
the mass are left out (:func:`model_reliant`): there the fixed point would be any body.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize_scalar

from massline.core.masslines import synthesise
from massline.core.rigid_body import RigidBody
from massline.core.plate import plate_coordinates
from massline.identify.warning_codes import CodedWarning
from massline.identify.resonances import PRECISION, RIGID, peaks, resolved, rigid_misfit
from massline.uff.recording import Recording

RELIANCE = 0.05  # a median departure in the band beyond this share of the masslines: the properties rest on the model
WINDOW = 1.15  # the FRFs within this factor of a resonance's frequency fit its scale
ABOVE = 1.5  # lines this factor above the record's top support mode weigh the body in every FRF: none left out
RELIANT = 0.3  # a line whose model departure exceeds this share of its pair's massline scale is left out
PLACINGS = 10  # steps at most that put the model's resonance on the record's peak before the search
SPREAD = 0.03  # the support's top mode searched this fraction either side (the record's peak may be a close one's)
GRID = 41  # scales tried before the one-dimensional search between the best one's neighbours
MOVED = 0.01  # the fixed point: a step moved the mass and each CoG coordinate by less than this many of their 1-σ
FLOOR = 1e-5  # … a 1-σ taken no smaller than this fraction of the mass and this many m (a noiseless record's is 0)
STEPS = 15  # identifications at most before the fixed point is declared not reached


@dataclass(frozen=True)
class SupportFit:
    """How the support model was fitted and what taking its departure off did.

    Attributes
    ----------
    stiffness, frequency : float
        Fitted scales on the support's springs and on the elastic natural frequencies (1: as described).
    recorded, modelled : (float, float)
        (top support mode, first elastic mode), Hz: the record's (nan where it resolves none) and the model's.
    departure : (float, float)
        The median and the largest |δ_ij(f)| in the band identified, over the masslines' RMS scale.
    moved : float
        The mass identified on H − δ over the one identified on H, minus 1.
    steps : int
        Identifications run; ``converged`` whether the fixed point was reached within STEPS.
    """

    stiffness: float
    frequency: float
    recorded: tuple
    modelled: tuple
    departure: tuple
    moved: float
    steps: int
    converged: bool

    @property
    def note(self) -> str:
        top, elastic = self.modelled
        return (
            f"the support and the elastic modes modelled with the mesh's FE model (springs × {self.stiffness:.3g}: "
            f"top support mode {top:.4g} Hz; elastic frequencies × {self.frequency:.3g}: first {elastic:.4g} Hz) "
            f"moved the FRFs off their masslines by a median {self.departure[0]:.2%} of their scale in the band "
            f"(up to {self.departure[1]:.3g}×); taken off, "
            + ("the FRFs as recorded fit no body" if np.isnan(self.moved) else
               f"the mass moves by {self.moved:+.2%} from identify's on the FRFs as recorded")
            + ("" if self.converged else f" (not settled after {self.steps} steps)")
        )

    @property
    def warnings(self) -> tuple:
        """Where the properties rest on the model: its departure from the masslines in the band is beyond RELIANCE
        (its median), or the fixed point was not reached."""
        said = []
        if self.departure[0] > RELIANCE or not self.converged:
            said.append(CodedWarning("support_model_reliance", (
                f"the support and the elastic modes move the band's FRFs off their masslines by a median "
                f"{self.departure[0]:.1%}: the properties rest on the support model taken off (springs and elastic "
                "frequencies fitted to the record's resonances), whose own error the ± does not hold"
                + ("" if self.converged else f", and its fixed point was not reached in {self.steps} steps")
                + "; a softer support opens a band that needs none")))  # fmt: skip
        return tuple(said)

    @property
    def payload(self) -> dict:
        return {
            "stiffness_scale": self.stiffness,
            "frequency_scale": self.frequency,
            "recorded_hz": [None if np.isnan(f) else f for f in self.recorded],
            "modelled_hz": list(self.modelled),
            "departure_median": self.departure[0],
            "departure_max": self.departure[1],
            "mass_moved": self.moved,
            "steps": self.steps,
            "converged": bool(self.converged),
        }


def misfit(model, body: RigidBody, recording: Recording, near: np.ndarray, scales: tuple) -> float:
    """Σ |H − A(θ) − δ(θ)|² over the lines ``near`` (a mask) and the pairs present, (m/s²/N)²."""
    f = recording.frequencies[near]
    rest = recording.frf[:, :, near] - synthesise(body, recording.sensors, recording.exciters).values[:, :, None]
    rest = rest - model.departure(body, f, recording.sensors, recording.exciters, *scales)
    return float(np.nansum(np.abs(rest) ** 2))


def fitted_scale(model, body: RigidBody, recording: Recording, scales: list, which: int, recorded: float) -> float:
    """The scale ``which`` (0: stiffness, 1: frequency) that fits the FRFs up to WINDOW above the ``recorded``
    top support mode (Hz: every support mode, and below them the springs alone, whatever the body), or within
    WINDOW of the first elastic one, the other scale as in ``scales``; unchanged where the record resolves none.

    The peak's line places the mode within half a line spacing Δf of it (:mod:`.resonances`), so the scale is
    searched where it puts the model's resonance within 2 Δf of the peak (and the support's top mode within
    SPREAD: two close modes make one peak): on GRID points, then between the best one's neighbours (a lightly
    damped elastic mode's misfit is a notch a few Δf wide)."""
    if not np.isfinite(recorded):
        return scales[which]
    power = 2.0 if which == 0 else 1.0  # a spring's mode moves with √k, an elastic one with the scale itself
    trial = list(scales)
    for _ in range(PLACINGS):  # gravity's share of the support's stiffness does not scale: a few steps
        modes = model.resonances(body, *trial)
        modelled = modes[1] if which else modes[0][-1]
        trial[which] *= (recorded / modelled) ** power
        if abs(np.log(recorded / modelled)) < 1e-5:
            break
    start = np.log(trial[which])
    f = recording.frequencies
    near = (f >= (recorded / WINDOW if which else 0.0)) & (f <= recorded * WINDOW)
    spacing = float(np.max(np.diff(f[near]))) if near.sum() > 1 else PRECISION * recorded

    def objective(log_scale: float) -> float:
        trial = list(scales)
        trial[which] = np.exp(log_scale)
        return misfit(model, body, recording, near, tuple(trial))

    grid = start + np.linspace(-1.0, 1.0, GRID) * power * max(2 * spacing / recorded, 0.0 if which else SPREAD)
    best = int(np.argmin([objective(x) for x in grid]))
    bounds = (grid[max(best - 1, 0)], grid[min(best + 1, GRID - 1)])
    found = minimize_scalar(objective, bounds=bounds, method="bounded", options={"xatol": 1e-7})
    return float(np.exp(found.x))


def departure_scale(delta: np.ndarray, recording: Recording, body: RigidBody, band: tuple) -> tuple[float, float]:
    """The median and the largest |δ| over the lines of ``band`` (Hz) and the pairs, each over the masslines' RMS
    scale of ``body``."""
    f = recording.frequencies
    inside = (f >= band[0]) & (f <= band[1])
    scale = np.sqrt(np.mean(synthesise(body, recording.sensors, recording.exciters).values ** 2))
    if not inside.any():
        return np.nan, np.nan
    size = np.abs(delta[:, :, inside]) / scale
    return float(np.nanmedian(size)), float(np.nanmax(size))


def record_resonances(recording: Recording, body: RigidBody, planar: bool) -> tuple[float, float]:
    """(top support mode, first elastic mode) of the whole record, Hz (nan where it resolves none).

    Its peaks that stand out of the masslines of ``body`` (:func:`.resonances.peaks`); a peak whose shape one
    rigid motion explains at the sensors and the hits is a support mode (:func:`.resonances.rigid_misfit`), the
    first other one above them the first elastic mode. On a stiff support the support's modes need not lie below
    any band a guess would give: the record as a whole is read."""
    f, frf = recording.frequencies, recording.frf
    S, E = (plate_coordinates(lines) if planar else lines.coordinates for lines in (recording.sensors,
                                                                                    recording.exciters))  # fmt: skip
    level = np.linalg.norm(synthesise(body, recording.sensors, recording.exciters).values)
    found = [k for k in peaks(f, frf, level) if f[k] > 0]
    rigid = [k for k in found if rigid_misfit(frf[:, :, k], S, E) < RIGID]
    elastic = [k for k in found if k not in rigid and (not rigid or k > max(rigid))]
    top = float(f[max(rigid)]) if rigid and resolved(f, max(rigid)) else np.nan
    first = float(f[elastic[0]]) if elastic and resolved(f, elastic[0]) else np.nan
    return top, first


def top_and_elastic(resonances: tuple) -> tuple[float, float]:
    """(top support mode, first elastic mode), Hz, of the model's ``resonances`` (:meth:`SupportModel.resonances`)."""
    modes, elastic = resonances
    return float(modes[-1]), float(elastic)


def model_reliant(springs: np.ndarray, masslines: np.ndarray) -> np.ndarray:
    """(n_s, n_e, n_f) bool: the lines of each FRF where the rigid body's departure on the support's springs
    (``springs``, the model without elastic modes) exceeds RELIANT of its pair's scale (the root of its row's and
    its column's RMS massline): there the FRF follows the springs more than the body's mass (below a stiff bounce
    it is the springs' whatever the mass), and what is left once the departure is taken off would be the model's
    own massline: identified there, any body would be a fixed point. An elastic mode's tail adds to the massline
    instead of taking its place, and its lines stay."""
    rows = np.sqrt(np.mean(masslines**2, axis=1))
    columns = np.sqrt(np.mean(masslines**2, axis=0))
    scale = np.sqrt(np.outer(rows, columns))
    return np.abs(springs) > RELIANT * scale[:, :, None]


def taken_off(
    recording: Recording,
    model,
    identify_once,
    start: RigidBody,
    recorded: tuple,
    band: tuple | None = None,
    plain: RigidBody | None = None,
) -> tuple[Recording, SupportFit]:
    """``recording`` with the support model's departure taken off at the fixed point, and the lines that rely on
    the model more than on the body left out (NaN: :func:`model_reliant`), and how it was fitted.

    ``identify_once(recording, band)`` identifies the body as tested (what the masslines weigh: its
    ``best.body``) on ``band`` (lo, hi) Hz, or on the band it chooses when None; the band chosen on the first
    corrected recording is kept for the steps after it (a band that moves from step to step moves the fixed point
    by the noise). ``start``: the body to begin from (the mesh's); ``plain``: identify's on the record as it came
    (None where it refuses it), which ``moved`` is from;
    ``recorded``: (top support mode, first elastic mode) the raw record resolves, Hz (nan: none). The scales are
    fitted on the whole record (its resonances), the body on the lines kept. Each step moves the body to the one
    identified, or a share of the way once a step moved it more than the one before (halved each time: near the
    support's modes the correction can move more than the body, and the plain map overshoots).
    """
    body, reliant = start, None
    scales, converged, steps, relaxation, last = [1.0, 1.0], False, 0, 1.0, np.inf
    while steps < STEPS and not converged:
        for which in (0, 1):
            scales[which] = fitted_scale(model, body, recording, scales, which, recorded[which])
        delta = model.departure(body, recording.frequencies, recording.sensors, recording.exciters, *scales)
        if reliant is None:  # fixed at the first step: lines that come and go move the fixed point by the noise
            springs = model.departure(body, recording.frequencies, recording.sensors, recording.exciters, *scales,
                                      elastic=False)  # fmt: skip
            reliant = model_reliant(springs, synthesise(body, recording.sensors, recording.exciters).values)
            if np.isfinite(recorded[0]):
                reliant &= (recording.frequencies < ABOVE * recorded[0])[None, None, :]
        corrected = replace(recording, frf=np.where(reliant, np.nan, recording.frf - delta),
                            coherence=None if recording.coherence is None else
                            np.where(reliant, np.nan, recording.coherence))  # fmt: skip
        found, steps = identify_once(corrected, band), steps + 1
        band = band or (found.band.low, found.band.high)
        again, reported = found.best.body, (found.band.low, found.band.high)
        sigma = np.maximum(np.concatenate([[found.std["mass"]], found.std["cog"]]), [FLOOR * body.mass, *[FLOOR] * 3])
        moved = np.abs(np.concatenate([[again.mass - body.mass], again.cog - body.cog]))
        converged = bool(np.all(moved <= MOVED * sigma))
        if np.max(moved / sigma) > last:  # the steps grow: a map that overshoots, damped
            relaxation /= 2
        last = np.max(moved / sigma)
        body = RigidBody.from_theta(body.theta + relaxation * (again.theta - body.theta))
    fit = SupportFit(
        stiffness=scales[0],
        frequency=scales[1],
        recorded=tuple(recorded),
        modelled=top_and_elastic(model.resonances(body, *scales)),
        departure=departure_scale(delta, recording, body, reported),
        moved=np.nan if plain is None else body.mass / plain.mass - 1,
        steps=steps,
        converged=converged,
    )
    return corrected, fit
