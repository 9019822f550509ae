"""``massline identify FILE.uff``: masslines from the recorded FRFs, then the properties with their 1-σ."""

from __future__ import annotations

import argparse

import numpy as np
from rich.console import Console
from rich.table import Table

from massline.identify.band import find_band, given_band
from massline.identify.estimator import TRANSVERSE, estimate
from massline.identify.massline_fit import fit_band
from massline.identify.uff import read_uff, to_recording
from massline.identify.uncertainty import property_std
from massline.placement.errors import MasslineError
from massline.placement.masslines import Masslines
from massline.placement.methods import DYNAMICS, KINEMATICS, identify
from massline.placement.rigid_body import RigidBody

from .output import claim_output, to_json, write_atomic

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
    parser.add_argument("--json", metavar="OUT", help="write the properties as JSON (DESIGN.md keys)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT")


def is_planar(data: Masslines) -> bool:
    """Plate data (§2.3): every line along ±z (where on the line its point sits does not matter)."""
    directions = (data.sensors + data.exciters).directions
    return bool(np.abs(directions[:, :2]).max() < PLANAR_TOLERANCE)


def results_table(body: RigidBody, std: dict, planar: bool, title: str) -> Table:
    table = Table(title=title)
    for col in ("quantity", "value", "± 1-σ", "unit"):
        table.add_column(col, justify="right")
    rows = [("mass", body.mass, std["mass"], "kg", 1.0)]
    rows += [(f"CoG {a}", body.cog[k], std["cog"][k], "mm", 1e3) for k, a in enumerate("xyz")]
    J, s = body.inertia_cog, std["inertia_cog"]
    rows += [(f"J_G {a}{b}", J[i, j], s[i, j], "kg·m²", 1.0) for i, j, a, b in _entries()]
    moments = std["principal_moments"]
    rows += [(f"principal moment {k + 1}", body.principal_moments[k], moments[k], "kg·m²", 1.0) for k in range(3)]
    rows += [(f"principal axis {k + 1}", np.nan, std["principal_axes_deg"][k], "°", 1.0) for k in range(3)]
    for name, value, sigma, unit, scale in rows:
        if planar and np.isnan(sigma):
            table.add_row(name, "unobservable", "", unit)
            continue
        shown = "" if np.isnan(value) else f"{value * scale:.6g}"
        table.add_row(name, shown, f"{sigma * scale:.2g}", unit)
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


def run(args: argparse.Namespace, console: Console) -> None:
    if args.json:
        claim_output(args.json, args.force)
    recording = to_recording(read_uff(args.uff))
    f = recording.frequencies
    zones = given_band(f, *args.band) if args.band else find_band(f, recording.frf)
    weights = None
    if recording.coherence is not None:
        gamma2 = np.clip(recording.coherence, 0.0, 1 - 1e-6)
        weights = gamma2 / (1 - gamma2)
    fit = fit_band(f, recording.frf, zones.low, zones.high, weights)
    data = Masslines(fit.values, recording.sensors, recording.exciters)
    planar = is_planar(data)
    sigma = np.maximum(fit.std, 1e-9 * np.abs(fit.values).max())
    console.print(
        f"massline band {zones.low:.1f}–{zones.high:.1f} Hz ({zones.rule}); band fits: median RMS residual "
        f"{np.median(fit.quality):.2%} of the massline, worst {fit.quality.max():.2%}; suspension and "
        f"residual-flexibility tails removed (a plain average would be off by up to {fit.bias.max():.1%})"
    )
    best = estimate(data, sigma, planar, args.transverse)
    std = property_std(data, sigma, best, draws=args.bootstrap)
    body = best.body
    if args.method != "best":
        kin, _, dyn = args.method.partition("+")
        found = identify(data, kin, dyn or kin)
        if found.mass is None:
            raise MasslineError(f"{args.method} does not identify the mass; choose a method 2 or 3 dynamics")
        body = found.body
    title = f"{args.uff}: identified properties ({args.method}; frame of the file; ± from the data)"
    console.print(results_table(body, std, planar, title))
    console.print(
        f"reduced χ² {best.chi2:.3g} over {data.values.size} masslines"
        + ("; physical-consistency constraint active" if best.constrained else "")
    )
    if args.json:
        write_atomic(args.json, to_json(payload(body, std, (zones.low, zones.high), planar)), args.force)
        console.print(f"wrote {args.json}")
