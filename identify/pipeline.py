"""Identification of a recording, as ``massline identify`` runs it: band, band fits, estimate, 1-σ.

``identify_recording`` is the pipeline a script calls; ``Identification`` holds what it found and
serialises itself as DESIGN.md's identify JSON (``payload``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from massline.identify.band_masslines import BandMasslines, band_residual, recording_band
from massline.identify.estimator import TRANSVERSE, Estimate, estimate
from massline.identify.exciter_mass import riding_masses
from massline.identify.identification_warnings import absent, identification_warnings
from massline.identify.mains import MainsLines, find_mains
from massline.identify.missing_pairs import check_determined, incomplete, unmeasured_notes
from massline.identify.massline_fit import BandFit
from massline.identify.plausibility import DENSITY_CODES, nominal_warnings
from massline.identify.recording_noise import RecordingNoise
from massline.identify.sensor_mass import Housings, file_labels, housing_points
from massline.identify.support_fit import SupportFit, record_resonances, taken_off
from massline.identify.suspicions import recording_warnings
from massline.identify.uncertainty import identified_spread
from massline.core.uncertainty_budget import UncertaintyBudget, limits
from massline.identify.warning_codes import CodedWarning, codes_of
from massline.identify.weighing import WeighedMass
from massline.core.band import Band
from massline.core.calibration import Calibration
from massline.core.errors import MasslineError, param
from massline.core.housing_masses import HousingMasses
from massline.core.masslines import Masslines
from massline.core.methods import DYNAMICS, KINEMATICS, identify
from massline.core.plate import plate_theta
from massline.core.files import to_json
from massline.core.properties import JSON_UNITS, reported_values
from massline.core.rigid_body import RigidBody
from massline.export.body import Body
from massline.export.units import SI, Units
from massline.uff.grid import to_recording
from massline.uff.runs import read_runs
from massline.uff.recording import Recording

PAPER_METHODS = [f"{k}+{d}" for k in KINEMATICS for d in DYNAMICS] + ["plate"]
PLANAR_TOLERANCE = 1e-6  # x, y components of a unit direction along z (UFF frames carry ~6 digits)
BEST, PLATE_OR_BEST = param("method", "'best'", cli="best"), param("method", "'plate' or 'best'", cli="plate or best")


def as_recording(recording: Recording | str | Path | list) -> Recording:
    """``recording`` itself, or the recording in the Universal File at that path, or in the files (or folders) of
    a list, one per run (:mod:`massline.uff.runs`)."""
    if isinstance(recording, Recording):
        return recording
    return to_recording(read_runs(recording if isinstance(recording, (list, tuple)) else [recording]))


def is_planar(sensors, exciters) -> bool:
    """Plate data (§2.3): every line along ±z (where on the line its point sits does not matter)."""
    directions = (sensors + exciters).directions
    return bool(np.abs(directions[:, :2]).max() < PLANAR_TOLERANCE)


def properties_payload(body: RigidBody, std: dict, band: tuple, planar: bool) -> dict:
    """DESIGN.md's identify JSON of a body and its 1-σ; unobservable plate entries are null (NaN here)."""
    values = reported_values(body, planar)
    std = {k: v for k, v in std.items() if k != "principal_axes_deg"}
    return {**values, "std": std, "band_hz": list(band), "planar": planar}


def check_method(
    method: str, planar: bool, weighed: WeighedMass | None = None, exciter_mass: float = 0.0, missing: int = 0
) -> None:
    """Refuse a paper method the data's lines cannot serve (the 3-D methods on plate data, the plate's on 3-D),
    or a scale's reading or a force gauge's mass with a paper method (they take no prior, and one body for every
    column), or ``missing`` pairs with a paper method (it solves the whole matrix)."""
    if missing and method != "best":
        raise MasslineError(
            f"method {method} (the paper's) needs every response against every reference, but {missing} pairs have "
            f"no massline: use {BEST}, which estimates from the pairs present"
        )
    if weighed is not None and method != "best":
        raise MasslineError(
            f"{param('weighed')} needs {BEST}: method {method} (the paper's) takes no prior on the mass"
        )
    if exciter_mass > 0 and method != "best":
        raise MasslineError(
            f"{param('exciter_mass')} needs {BEST}: method {method} (the paper's) takes one body for every column"
        )
    if planar and method not in ("best", "plate"):
        raise MasslineError(
            f"method {method} needs 3-D lines, but every line in this recording is along z (plate data): "
            f"use {PLATE_OR_BEST}"
        )
    if not planar and method == "plate":
        raise MasslineError(
            "method plate needs every line along z (plate data), but this recording has lines off z: "
            f"use {BEST} or a 3-D method such as method2+method3"
        )


def paper_body(data: Masslines, method: str, best: Estimate) -> RigidBody:
    """The body a paper method identifies; the plate's unobservable entries kept as the estimate's (never shown)."""
    kin, _, dyn = method.partition("+")
    found = identify(data, kin, dyn or kin)
    if found.mass is None:
        raise MasslineError(f"{method} does not identify the mass; choose a method 2 or 3 dynamics")
    if method == "plate":
        return best.model.body(plate_theta(found.mass, found.cog, found.inertia_cog))
    return found.body


def usable_lines(recording: Recording) -> tuple[Recording, tuple[CodedWarning, ...]]:
    """The recording without its lines at or below 0 Hz, and a note saying so when there were any."""
    kept = recording.above_zero()
    dropped = len(recording.frequencies) - len(kept.frequencies)
    if not dropped:
        return recording, ()
    if not len(kept.frequencies):
        raise MasslineError("the recording has no line above 0 Hz: export the FRFs over a frequency range")
    lines = "the 0 Hz line" if dropped == 1 and recording.frequencies[0] == 0 else f"{dropped} lines at or below 0 Hz"
    return kept, (CodedWarning("dc_line_set_aside", f"{lines} set aside (an exporter's DC line holds no massline)"),)


def without_mains(recording: Recording) -> tuple[Recording, MainsLines | None, tuple[CodedWarning, ...]]:
    """The recording without the lines of any mains interference (:mod:`.mains`), what was found, and a note
    saying which lines were set aside."""
    mains = find_mains(recording.frequencies, recording.frf)
    if mains is None:
        return recording, None, ()
    return recording.kept(~mains.aside), mains, (CodedWarning("mains_set_aside", mains.note),)


@dataclass(frozen=True, eq=False, kw_only=True)
class Identification:
    """What identify found in a recording: the band, each FRF's band fit, the estimate and its 1-σ.

    ``band``'s ``suspension_top`` and ``first_elastic`` are the support's top mode and the first elastic mode
    as the record resolves them around it (:func:`.resonances.bounding_modes`; nan where it shows none): the
    frequencies the warnings and the reports quote.

    ``body`` is the reported body: the weighted estimate's, or a paper method's (``method``), with the
    accelerometer ``housings`` taken off; ``best`` is the weighted estimate of the body as tested (what the
    masslines weigh) and ``tested`` / ``tested_std`` the reported body and 1-σ before the housings are taken off
    (the same as ``body`` / ``std`` without housings). ``weighed`` is the scale's reading of the bare body, when
    given. ``recording`` is the one identified: the file's without its lines at or below 0 Hz and the lines of
    any mains interference (``mains``); ``notes`` say what was set aside. ``exciter_mass`` is the force gauges'
    structure-side mass (kg) each column was fitted with (0: a hammer), never part of ``body``. ``noise`` is each
    FRF's noise over the band as the recording shows it (:mod:`.recording_noise`), the one every fit is measured
    against. ``budget`` is ``std``'s split by source (:mod:`.uncertainty_budget`).
    """

    recording: Recording
    band: Band
    fit: BandFit
    data: Masslines
    sigma: np.ndarray
    planar: bool
    best: Estimate
    std: dict
    body: RigidBody
    method: str = "best"
    notes: tuple = ()
    warnings: tuple = ()
    housings: Housings = Housings()
    tested: RigidBody | None = None
    tested_std: dict | None = None
    weighed: WeighedMass | None = None
    exciter_mass: float = 0.0
    mains: MainsLines | None = None
    support_fit: SupportFit | None = None
    noise: RecordingNoise | None = None
    budget: UncertaintyBudget | None = None

    @property
    def noise_payload(self) -> dict | None:
        """The recording's noise over the band (relative RMS, how it was found, the line differences' check) and
        the band fits' relative RMS residual against it (NaN on a noiseless recording; None: not measured)."""
        if self.noise is None:
            return None
        residual, level = band_residual(self.fit, self.noise), self.noise.relative()
        return {**self.noise.payload, "fit": residual, "fit_over_noise": residual / level if level > 0 else np.nan}

    @property
    def budget_payload(self) -> dict:
        """identify JSON's ``uncertainty_budget``: the calibration assumed, each quantity's 1-σ split by source
        (:meth:`massline.core.uncertainty_budget.UncertaintyBudget.payload`), and the sentences naming what limits
        it (``limits``)."""
        return self.budget.payload() | {"limits": limits(self.budget, self.body)}

    @property
    def payload(self) -> dict:
        """DESIGN.md's identify JSON: the bare body, and ``as_tested`` when housings were taken off."""
        band = (self.band.low, self.band.high)
        found = properties_payload(self.body, self.std, band, self.planar)
        chi2 = self.best.chi2 if np.isfinite(self.best.chi2) else None
        found |= {
            "chi2_reduced": chi2,
            "warnings": [w.as_json() for w in self.warnings],
            "sensor_mass": self.housings.payload(),
        }
        found["exciter_mass"] = self.exciter_mass
        found["runs"] = list(self.recording.runs)  # the files merged, one per run (empty: one file)
        found["mains"] = None if self.mains is None else self.mains.parameters  # the lines set aside, Hz
        found["support_model"] = None if self.support_fit is None else self.support_fit.payload
        found["noise"] = self.noise_payload
        found["uncertainty_budget"] = None if self.budget is None else self.budget_payload
        found["units"] = JSON_UNITS
        if self.housings.count:
            found["as_tested"] = properties_payload(self.tested, self.tested_std, band, self.planar)
        return found

    @property
    def mass(self) -> float:
        """The reported body's mass, kg."""
        return self.body.mass

    @property
    def cog(self) -> np.ndarray:
        """The reported body's CoG, m, frame of the recording (a plate's z_G: NaN, unobserved)."""
        return np.asarray(reported_values(self.body, self.planar)["cog"], dtype=float)

    @property
    def inertia(self) -> np.ndarray:
        """The reported body's inertia tensor about the CoG, kg·m², tensor sign (J_xy = −∫xy dm), frame of the
        recording (a plate's z row and column: NaN, unobserved)."""
        return np.asarray(reported_values(self.body, self.planar)["inertia_cog"], dtype=float)

    def to_json(self) -> str:
        """DESIGN.md's identify JSON (``payload``) as text, NaN as null."""
        return to_json(self.payload)

    def measured(self, as_tested: bool = False, source: str = "") -> Body:
        """The body as measured, with its 1-σ and a note of what was measured (``source``: the recording's name):
        the reported body, or with ``as_tested`` the body with the accelerometer housings on."""
        body, std = (self.tested, self.tested_std) if as_tested else (self.body, self.std)
        values = reported_values(body, self.planar)
        note = identification_note(self, as_tested, source)
        return Body(mass=body.mass, cog=values["cog"], inertia=values["inertia_cog"], std=std, note=note,
                    warnings=self.warnings)  # fmt: skip

    def export(self, path: str | Path, units: str | Units = SI, *, as_tested: bool = False, force: bool = False,
               source: str = "") -> Path:  # fmt: skip
        """Write the body (``measured``) to ``path`` in the format its suffix names (``massline.export.FORMATS``),
        in ``units`` ('m-kg', 'mm-kg', 'mm-t'); an existing file only with ``force``."""
        return self.measured(as_tested, source).export(path, units, force)


NONE_TAKEN_OFF = (
    "the body with its accelerometers on, none taken off (no sensor mass given): the bare body only if they weigh "
    "nothing"
)


def fit_note(found: Identification) -> str:
    """'method best, band 5-40 Hz, 72 masslines, reduced chi2 1.02': how ``found`` was identified."""
    fit = f"reduced chi2 {found.best.chi2:.3g}" if np.isfinite(found.best.chi2) else "no redundancy to check the fit"
    band = f"band {found.band.low:.4g}-{found.band.high:.4g} Hz"
    return f"method {found.method}, {band}, {int(np.isfinite(found.sigma).sum())} masslines, {fit}"


def identification_note(found: Identification, as_tested: bool, source: str) -> str:
    """What an export of ``found`` holds: the recording, how it was identified, the body as tested or bare."""
    housings = found.housings
    grams = housings.describe().replace("×", "x")  # exports are ASCII
    if not housings.count:
        which = NONE_TAKEN_OFF
    else:
        which = f"the body as tested, {grams} on" if as_tested else f"the bare body, {grams} taken off"
    return f"{source or 'a recording'}, massline identify ({fit_note(found)}); {which}"


def identify_recording(
    recording: Recording | str | Path,
    band=None,
    transverse: float = TRANSVERSE,
    *,
    draws: int = 100,
    method: str = "best",
    sensor_mass: float | HousingMasses = 0.0,
    exciter_mass: float = 0.0,
    weighed: WeighedMass | None = None,
    support=None,
    calibration: Calibration | None = None,
) -> Identification:
    """The band (``band`` (lo, hi) Hz, or found), the band fits, the estimate and its 1-σ (``draws`` bootstrap).

    ``recording``: a ``Recording``, or the path of a Universal File (read as ``massline identify`` reads it);
    ``sensor_mass``: each accelerometer housing's mass (kg, or per point label: :class:`HousingMasses`), taken
    off the body as tested (:mod:`.sensor_mass`);
    ``exciter_mass``: each force gauge's structure-side mass (kg), riding at its drive point while it drives, so
    that each column is fitted on its own body and the one reported is without them (:mod:`.exciter_mass`);
    ``weighed``: a scale's reading of the bare body, a prior on the mass (:mod:`.weighing`);
    ``support``: the support and the body's elastic modes as the mesh's FE model gives them
    (:class:`massline.virtual.support_model.SupportModel`): each FRF's departure from its massline is taken off
    first (:mod:`.support_fit`), and ``support_fit`` says how;
    ``calibration``: the chain's type-B 1-σ (:class:`massline.core.calibration.Calibration`; default 1 % for each
    accelerometer and the force transducer, its ``transverse`` replaced by ``transverse``), which join the
    1-σ's budget (:mod:`.uncertainty_budget`).
    """
    calibration = replace(calibration or Calibration(), transverse=transverse)
    options = dict(transverse=transverse, sensor_mass=sensor_mass, exciter_mass=exciter_mass, weighed=weighed)
    if support is not None:
        corrected, fit = support_corrected(as_recording(recording), band, support, **options)
        found = identify_recording(corrected, band, draws=draws, method=method, calibration=calibration, **options)
        notes = found.notes + (CodedWarning("support_modelled", fit.note),)
        return replace(found, support_fit=fit, notes=notes, warnings=found.warnings + fit.warnings)
    recording, notes = usable_lines(as_recording(recording))
    notes += unmeasured_notes(recording.unmeasured_nodes)
    recording, mains, aside = without_mains(recording)
    planar = is_planar(recording.sensors, recording.exciters)
    check_method(method, planar, weighed, exciter_mass)
    riding = riding_masses(recording.exciters, exciter_mass, planar)
    chosen, used = recording_band(recording, band, planar)
    fitted = BandMasslines.of(recording, used)
    check_method(method, planar, weighed, exciter_mass, fitted.missing)
    check_determined(fitted.data, fitted.present, planar, (recording.sensor_channels, recording.exciter_channels))
    housings = Housings.on(recording.sensors, sensor_mass, file_labels(recording))
    prior = None if weighed is None else weighed.plus(housings.total)
    best = estimated(recording, chosen, fitted, planar, transverse, prior=prior, riding=riding)
    bare = housings.removed(best)  # refused first when the housings leave no physical body
    spread = identified_spread(fitted.data, fitted.sigma, fitted.truncation, best, bare=bare, housings=housings,
                               draws=draws, calibration=calibration)  # fmt: skip
    tested = best.body if method == "best" else paper_body(fitted.data, method, best)
    warnings = identification_warnings(recording, (chosen, used), fitted, best, spread, weighed=weighed,
                                       housings=housings, bare=bare.body, tested=tested)  # fmt: skip
    return Identification(
        recording=recording, band=used, fit=fitted.fit, data=fitted.data, sigma=fitted.sigma, planar=planar, best=best,
        std=spread.bare, body=housings.removed_from(tested, planar), method=method, notes=notes + aside,
        warnings=warnings, housings=housings, tested=tested, tested_std=spread.tested, weighed=weighed,
        exciter_mass=exciter_mass, mains=mains, noise=fitted.noise, budget=spread.budget,
    )  # fmt: skip


def estimated(
    recording: Recording, chosen: Band, masslines: BandMasslines, planar: bool, transverse: float, *, prior, riding
) -> Estimate:
    """The weighted estimate of the band fits' ``masslines`` (:func:`.estimator.estimate`, with the scale's reading
    ``prior`` of the body as tested and the exciters' ``riding`` masses); where it is refused, what ``recording``
    says against its ``chosen`` band is said too, the likely reason."""
    try:
        return estimate(masslines.data, masslines.sigma, planar, transverse, weighed=prior, riding=riding)
    except MasslineError as refused:
        f, frf, coherence = recording.frequencies, recording.frf, recording.coherence
        against = recording_warnings(f, frf, coherence, chosen, recording.exponential_window)
        lacks = incomplete(absent(recording, recording.present), recording.present.size, recording.unmeasured_nodes)
        said = [str(refused)] + [w.text for w in against] + ([lacks] if lacks else [])
        raise MasslineError("; ".join(said)) from None


def support_corrected(recording: Recording, band, support, **options) -> tuple[Recording, SupportFit]:
    """``recording`` with the ``support`` model's departure from the masslines taken off (:mod:`.support_fit`),
    begun from the mesh's body (identify's on a stiff support's record can be far off, and the support's modes
    placed with it farther), and how it was fitted, with how far the mass moved from identify's on the record as
    it came (nan where identify refuses it); ``options``: :func:`identify_recording`'s (transverse,
    sensor_mass, exciter_mass, weighed)."""
    try:
        plain = identify_recording(recording, band, draws=0, **options).best.body
    except MasslineError:  # a band squeezed past use
        plain = None
    usable, _ = usable_lines(recording)
    recorded = record_resonances(usable, support.body, is_planar(usable.sensors, usable.exciters))
    once = lambda r, b: identify_recording(r, b, draws=0, **options)  # noqa: E731
    return taken_off(recording, support, once, support.body, recorded, band, plain)


def against_nominal(found: Identification, nominal: RigidBody | None) -> Identification:
    """``found`` with its mass weighed against the ``nominal`` body's (a mesh given to identify), which decides the
    9.81× suspicion in the density's place (:func:`.plausibility.nominal_warnings`)."""
    if nominal is None:
        return found
    kept = tuple(w for w in found.warnings if w.code not in DENSITY_CODES)
    housings = len(housing_points(found.recording.sensors))
    misfit = "model_misfit" in codes_of(found.warnings)
    against = nominal_warnings(found.body, nominal, found.std["mass"], housings, misfit)
    return replace(found, warnings=kept + tuple(against))
