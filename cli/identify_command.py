"""``massline identify FILE.uff``: masslines from the recorded FRFs, then the properties with their 1-σ."""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import numpy as np
from massline.identify.band import Zones, find_band, given_band
from massline.identify.estimator import TRANSVERSE, Estimate, estimate
from massline.identify.massline_fit import BandFit, fit_band
from massline.identify.uncertainty import property_std
from massline.meshargs import add_nominal_arguments, nominal_mesh
from massline.placement.errors import MasslineError
from massline.placement.files import claim_output, to_json, write_atomic, write_report
from massline.placement.masslines import Masslines
from massline.placement.methods import DYNAMICS, KINEMATICS, identify
from massline.placement.rigid_body import RigidBody
from massline.uff.reader import read_uff, to_recording
from massline.uff.recording import Recording
from rich.console import Console
from rich.table import Table

PAPER = [f"{k}+{d}" for k in KINEMATICS for d in DYNAMICS] + ["plate"]
PLANAR_TOLERANCE = 1e-6  # x, y components of a unit direction along z (UFF frames carry ~6 digits)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("uff", metavar="FILE.uff", help="FRFs exported by the test software (UFF 58/58b)")
    parser.add_argument("--band", type=float, nargs=2, metavar=("LO", "HI"), help="massline band, Hz (default: found)")
    parser.add_argument(
        "--method",
        default="best",
        choices=["best", *PAPER],
        help="'best' (weighted, consistent, all masslines; default) or the paper's KINEMATICS+DYNAMICS",
    )
    parser.add_argument(
        "--transverse",
        type=float,
        default=TRANSVERSE,
        metavar="FRACTION",
        help=f"prior 1-σ of each accelerometer's transverse sensitivity (default {TRANSVERSE}; 0: exact axes)",
    )
    parser.add_argument("--bootstrap", type=int, default=100, metavar="N", help="bootstrap draws over the sensors")
    add_nominal_arguments(parser)
    parser.add_argument("--json", metavar="OUT", help="write the properties as JSON (DESIGN.md keys)")
    parser.add_argument("--report", metavar="OUT.html", help="write the identification report (one HTML page)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT and OUT.html")


def is_planar(data: Masslines) -> bool:
    """Plate data (§2.3): every line along ±z (where on the line its point sits does not matter)."""
    directions = (data.sensors + data.exciters).directions
    return bool(np.abs(directions[:, :2]).max() < PLANAR_TOLERANCE)


def quantities(body: RigidBody) -> list[tuple[str, float, str, float]]:
    """(name, value SI, unit shown, scale to it) of every reported property (nan for the principal axes)."""
    J = body.inertia_cog
    rows = [("mass", body.mass, "kg", 1.0)]
    rows += [(f"CoG {a}", body.cog[k], "mm", 1e3) for k, a in enumerate("xyz")]
    rows += [(f"J_G {a}{b}", J[i, j], "kg·m²", 1.0) for i, j, a, b in _entries()]
    rows += [(f"principal moment {k + 1}", body.principal_moments[k], "kg·m²", 1.0) for k in range(3)]
    return rows + [(f"principal axis {k + 1}", np.nan, "°", 1.0) for k in range(3)]


def sigmas(std: dict) -> list[float]:
    """The 1-σ of :func:`quantities`' rows, SI (degrees for the axes)."""
    s = std["inertia_cog"]
    return [std["mass"], *std["cog"], *(s[i, j] for i, j, _, _ in _entries()), *std["principal_moments"]] + list(
        std["principal_axes_deg"]
    )


def results_table(body: RigidBody, std: dict, planar: bool, title: str, nominal: RigidBody | None = None) -> Table:
    table = Table(title=title)
    for col in ("quantity", "value", "± 1-σ", "unit") + (() if nominal is None else ("nominal (mesh)",)):
        table.add_column(col, justify="right")
    nominal_rows = quantities(body) if nominal is None else quantities(nominal)
    for (name, value, unit, scale), sigma, (_, reference, _, _) in zip(quantities(body), sigmas(std), nominal_rows):
        extra = () if nominal is None else ("" if np.isnan(reference) else f"{reference * scale:.6g}",)
        if planar and np.isnan(sigma):
            table.add_row(name, "unobservable", "", unit, *extra)
            continue
        shown = "" if np.isnan(value) else f"{value * scale:.6g}"
        table.add_row(name, shown, f"{sigma * scale:.2g}", unit, *extra)
    return table


def _entries():
    names = "xyz"
    return [(i, j, names[i], names[j]) for i in range(3) for j in range(i, 3)]


def payload(body: RigidBody, std: dict, band: tuple, planar: bool) -> dict:
    """The identify JSON of DESIGN.md; unobservable plate entries are null."""
    values = {**body.as_dict()}
    if planar:
        values["cog"] = [*values["cog"][:2], np.nan]
        J = np.array(values["inertia_cog"], dtype=float)
        J[2, :] = J[:, 2] = np.nan
        values["inertia_cog"] = J
    std = {k: v for k, v in std.items() if k != "principal_axes_deg"}
    return {**values, "std": std, "band_hz": list(band), "planar": planar}


@dataclass(frozen=True, eq=False)
class Identification:
    """What identify found in a recording: the band, each FRF's band fit, the estimate and its 1-σ.

    ``body`` is the reported body: the weighted estimate's, or a paper method's (``method``).
    """

    recording: Recording
    zones: Zones
    fit: BandFit
    data: Masslines
    sigma: np.ndarray
    planar: bool
    best: Estimate
    std: dict
    body: RigidBody
    method: str = "best"


def identify_recording(
    recording: Recording, band=None, transverse: float = TRANSVERSE, draws: int = 100, method: str = "best"
) -> Identification:
    """The band (``band`` (lo, hi) Hz, or found), the band fits, the estimate and its 1-σ (``draws`` bootstrap)."""
    f = recording.frequencies
    zones = given_band(f, *band) if band else find_band(f, recording.frf)
    weights = None
    if recording.coherence is not None:
        gamma2 = np.clip(recording.coherence, 0.0, 1 - 1e-6)
        weights = gamma2 / (1 - gamma2)
    fit = fit_band(f, recording.frf, zones.low, zones.high, weights)
    data = Masslines(fit.values, recording.sensors, recording.exciters)
    planar = is_planar(data)
    sigma = np.maximum(fit.std, 1e-9 * np.abs(fit.values).max())
    best = estimate(data, sigma, planar, transverse)
    std = property_std(data, sigma, best, draws=draws)
    body = best.body
    if method != "best":
        kin, _, dyn = method.partition("+")
        found = identify(data, kin, dyn or kin)
        if found.mass is None:
            raise MasslineError(f"{method} does not identify the mass; choose a method 2 or 3 dynamics")
        body = found.body
    return Identification(recording, zones, fit, data, sigma, planar, best, std, body, method)


def run(args: argparse.Namespace, console: Console) -> None:
    for path in (args.json, args.report):
        if path:
            claim_output(path, args.force)
    mesh = nominal_mesh(args)
    recording = to_recording(read_uff(args.uff))
    found = identify_recording(recording, args.band, args.transverse, args.bootstrap, args.method)
    zones, fit = found.zones, found.fit
    console.print(
        f"massline band {zones.low:.1f}–{zones.high:.1f} Hz ({zones.rule}); band fits: median RMS residual "
        f"{np.median(fit.quality):.2%} of the massline, worst {fit.quality.max():.2%}; suspension and "
        f"residual-flexibility tails removed (a plain average would be off by up to {fit.bias.max():.1%})"
    )
    title = f"{args.uff}: identified properties ({args.method}; frame of the file; ± from the data)"
    nominal = None if mesh is None else mesh.nominal
    console.print(results_table(found.body, found.std, found.planar, title, nominal))
    console.print(
        f"reduced χ² {found.best.chi2:.3g} over {found.data.values.size} masslines"
        + ("; physical-consistency constraint active" if found.best.constrained else "")
    )
    if args.json:
        band = (zones.low, zones.high)
        write_atomic(args.json, to_json(payload(found.body, found.std, band, found.planar)), args.force)
        console.print(f"wrote {args.json}")
    if args.report:
        from massline.reports.identification_report import identify_report

        write_report(console, args.report, lambda: identify_report(found, args.uff, mesh), args.force)
