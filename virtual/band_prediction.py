"""Pre-test check: where the massline band lies, and the support that widens it.

Zone B of Appendix A is the band where the accelerance of the suspended, elastic body stays close to the
free rigid body's massline H₀ = S M_O⁻¹ Wᵀ: above the suspension modes (zone A, error ≈ (f_s/f)²) and below
the first elastic mode (zone C, error ≈ (f/f_a)²). A band is held when every single FRF stays within the
tolerance of its massline's scale (:func:`massline.core.band.held_band`); a weak FRF (a sensor nearly
square to the motion a hit drives) strays most, so the tolerance is the tightest of ``TOLERANCES`` at which
the band is at least ``MIN_RATIO`` wide.
"""

from __future__ import annotations

from itertools import islice

import numpy as np

from massline.core.band import Band, held_band, stray
from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.core.rigid_body import RigidBody
from massline.virtual.attachment import UP, point_above
from massline.virtual.suspended import SuspendedBody
from massline.virtual.rigging import Rig, rig
from massline.virtual.suspension import CORD_LENGTH, GRAVITY, STRETCH, Cord, Suspension

TOLERANCES = (0.01, 0.02, 0.05)  # every FRF within 1 %, else 2 %, else 5 % of its massline
MIN_RATIO = 2.0  # a band at least an octave wide holds at the tolerance chosen
PIVOTS = (0.02, 0.05)  # m above the CoG: a bridle apex close above it (Appendix A), where nothing is above
HIGHER = (0.5, 1.0, 2.0)  # apexes this many body heights above the body's top, tried where no pivot can be rigged
BISECTIONS = 12  # halvings of a grid step (1.4 % of f) that place each band edge


def strays(model: SuspendedBody, sensors: Lines, exciters: Lines, frequencies: np.ndarray) -> np.ndarray:
    """max_ij |H_ij(f) − A_ij|/s_ij at each frequency (Hz): how far the farthest FRF sits from its massline, against
    its scale (:func:`massline.core.band.frf_scales`)."""
    H = model.accelerance(frequencies, sensors.points, sensors.directions, exciters.points, exciters.directions)
    return stray(H, synthesise(model.loaded, sensors, exciters).values)  # the accelerometers are weighed too


def frequency_axis(model: SuspendedBody, points: int = 600) -> np.ndarray:
    """A log-spaced axis from a tenth of the top suspension mode to twice the first elastic mode, Hz."""
    low = max(0.1 * model.suspension_frequencies.max(), 0.1)
    high = 2 * model.first_elastic_frequency if model.n_elastic else 1000 * low
    return np.geomspace(low, high, points)


def edge(model: SuspendedBody, sensors: Lines, exciters: Lines, held: float, lost: float, tolerance: float) -> float:
    """The band edge between a held frequency and a lost one (Hz), by bisection in log frequency."""
    for _ in range(BISECTIONS):
        middle = np.sqrt(held * lost)
        if strays(model, sensors, exciters, np.array([middle]))[0] <= tolerance:
            held = middle
        else:
            lost = middle
    return float(held)


def band_of(model: SuspendedBody, sensors: Lines, exciters: Lines, f: np.ndarray, found, tolerance: float) -> Band:
    """The Band of the run ``found`` (low, high) on axis ``f`` (Hz), its edges placed between grid lines."""
    low, high = found
    if np.isfinite(low):
        k, j = np.searchsorted(f, low), np.searchsorted(f, high)
        low = edge(model, sensors, exciters, low, f[k - 1], tolerance) if k > 0 else low
        if j < len(f) - 1:
            high = edge(model, sensors, exciters, high, f[j + 1], tolerance)
        elif not model.n_elastic:
            high = np.inf  # a rigid model has no zone C
    top, elastic = float(model.suspension_frequencies.max()), model.first_elastic_frequency
    return Band(low, high, top, elastic, "predicted", tolerance)


def tightest(runs: dict) -> float:
    """The first tolerance (key of ``runs``: tolerance → list of (low, high)) at which some run is MIN_RATIO
    wide; the loosest when none is."""
    wide = (tol for tol, found in runs.items() if any(hi / lo >= MIN_RATIO for lo, hi in found))
    return next(wide, list(runs)[-1])


def predict_band(model: SuspendedBody, sensors: Lines, exciters: Lines, tolerance: float | None = None) -> Band:
    """The widest run of frequencies where every FRF stays within ``tolerance`` of its massline (None: the
    tightest of TOLERANCES that holds a band MIN_RATIO wide)."""
    return choose_support([model], sensors, exciters, tolerance)[0][1]


def choose_support(
    models: list[SuspendedBody], sensors: Lines, exciters: Lines, tolerance: float | None = None
) -> list[tuple[SuspendedBody, Band]]:
    """Each model with its band, the widest first, all at one tolerance: ``tolerance``, or (None) the tightest
    of TOLERANCES at which some model holds a band MIN_RATIO wide."""
    axes = [frequency_axis(m) for m in models]
    lines = [strays(m, sensors, exciters, f) for m, f in zip(models, axes)]
    candidates = (tolerance,) if tolerance else TOLERANCES
    runs = {tol: [held_band(f, s, tol) for f, s in zip(axes, lines)] for tol in candidates}
    chosen = tightest(runs)
    bands = [band_of(m, sensors, exciters, f, run, chosen) for m, f, run in zip(models, axes, runs[chosen])]
    order = sorted(range(len(models)), key=lambda k: -np.nan_to_num(np.log(bands[k].ratio), nan=-np.inf))
    return [(models[k], bands[k]) for k in order]


def support_candidates(mesh, body: RigidBody, up=UP) -> list[Suspension]:
    """The supports a plan chooses from: Appendix A's soft long cord hung at each pivot straight above the CoG
    (where the vertical leaves the body, and a bridle apex ``PIVOTS`` above the CoG where nothing of the body
    lies over it) that a technician can rig (:func:`support_rig`: a bridle's legs reach the apex; where none of
    these can be rigged, the lowest of ``HIGHER`` apexes above the body's top that can), and the foam pad under the
    lowest points where the body can rest on one."""
    top, on_surface = point_above(mesh, body.cog, up)
    height = float((top - body.cog) @ up)
    heights = sorted({height} | {h for h in PIVOTS if h > height or not on_surface})
    size = float(np.ptp(mesh.vertices @ up))
    riggable = [h for h in heights if support_rig(mesh, body, body.cog + h * up, up) is not None]
    higher = (h for h in (height + f * size for f in HIGHER) if support_rig(mesh, body, body.cog + h * up, up))
    heights = riggable or list(islice(higher, 1)) or heights
    supports = [Suspension(cords=(Cord.soft(body.cog + h * up, body.mass),), up=up) for h in heights]
    try:
        supports.append(Suspension.parse("foam", mesh, body))
    except MasslineError:  # no underside the body can rest on
        pass
    return supports


def support_rig(mesh, body: RigidBody, apex: np.ndarray, up=UP) -> Rig | None:
    """The rig of a cord tied at ``apex`` (3,) m straight above the CoG of ``body`` (:mod:`.rigging`): tied on the
    surface where the vertical leaves the body there, else a bridle whose legs carry the weight; None when no
    bridle reaches the apex (inside a bore, under an overhang)."""
    top, on_surface = point_above(mesh, body.cog, up)
    tied = on_surface and np.linalg.norm(top - apex) <= 1e-9 * max(float(np.ptp(mesh.vertices)), 1e-300)
    return rig(mesh, apex, body.mass * GRAVITY, up, bool(tied))


def recommend_suspension(
    model: SuspendedBody, top_point: np.ndarray, stretch: float = STRETCH, length: float = CORD_LENGTH, up=UP
) -> Suspension:
    """Appendix A's advice made concrete: one soft, long cord attached close above the CoG.

    Parameters
    ----------
    model : SuspendedBody
        The body as planned (its mass sets the cord stiffness).
    top_point : (3,) array
        Attachment point: the body's surface point straight above the CoG, m.
    stretch : float
        Static stretch of the cord under the weight, m: k = m g / stretch, so the bounce
        mode sits at √(g/stretch)/2π (1.0 Hz for 0.25 m).
    length : float
        Hanging length, m: the pendulum modes fall as √(g/L).
    """
    return Suspension(cords=(Cord.soft(top_point, model.loaded.mass, stretch, length),), up=up)
