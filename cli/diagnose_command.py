"""``massline diagnose FILE.uff``: where the recording departs from the rigid body, and which physics was left out."""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import numpy as np
from massline.identify.band import Zones, estimation_band, find_band, given_band
from massline.identify.diagnose.diagnosis import Diagnosis, diagnose, property_std, relative_noise, roomy
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.notes import finding_note, finding_payload
from massline.identify.diagnose.screens import kinematic_matrix, rigid_subspace_residual, screen
from massline.identify.estimator import TRANSVERSE
from massline.identify.tails import BandData
from massline.identify_command import is_planar, payload
from massline.meshargs import add_nominal_arguments, nominal_mesh
from massline.placement.files import claim_output, to_json, write_atomic, write_atomic_bytes, write_report
from massline.placement.masslines import Masslines
from massline.reports.diagnosis_figures import diagnosis_figure
from massline.uff.datasets import channel_name
from massline.uff.reader import read_uff, to_recording
from massline.uff.recording import Recording
from rich.console import Console
from rich.table import Table


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("uff", metavar="FILE.uff", help="FRFs exported by the test software (UFF 58/58b)")
    parser.add_argument("--band", type=float, nargs=2, metavar=("LO", "HI"), help="massline band, Hz (the plan's)")
    add_nominal_arguments(parser)
    parser.add_argument(
        "--transverse", type=float, default=TRANSVERSE, metavar="FRACTION", help="accelerometers' cross-axis prior"
    )
    parser.add_argument("--json", metavar="OUT", help="write the findings, fit and properties as JSON")
    parser.add_argument("--plot", metavar="PNG", help="residual maps and FRF overlays before and after")
    parser.add_argument("--report", metavar="OUT.html", help="write the diagnosis report (one HTML page)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT, PNG and OUT.html")


def labels(recording) -> tuple[list[str], list[str]]:
    """'node:±X' names of the channels, or their numbers when the recording carries no labels."""
    if recording.sensor_labels is None:
        return [f"sensor {i + 1}" for i in range(len(recording.sensors))], [
            f"hit {j + 1}" for j in range(len(recording.exciters))
        ]
    return [channel_name(*c) for c in recording.sensor_labels], [channel_name(*c) for c in recording.exciter_labels]


def properties_table(result: Diagnosis, nominal) -> Table:
    table = Table(title="properties before and after the diagnosis (frame of the file; ± 1-σ of the fit)")
    table.caption = "estimated over the found band with the suspension and residual-flexibility tails, as identify does"
    for col in ("quantity", "before", "after", "± 1-σ", "nominal (mesh)", "unit"):
        table.add_column(col, justify="right")
    before, after, std = result.estimates[0].body, result.corrected, property_std(result.estimates[1])
    rows = [("mass", lambda b: b.mass, lambda s: s["mass"], "kg", 1.0)]
    rows += [(f"CoG {a}", lambda b, k=k: b.cog[k], lambda s, k=k: s["cog"][k], "mm", 1e3) for k, a in enumerate("xyz")]
    rows += [
        (
            f"principal moment {k + 1}",
            lambda b, k=k: b.principal_moments[k],
            lambda s, k=k: s["principal_moments"][k],
            "kg·m²",
            1.0,
        )
        for k in range(3)
    ]
    for name, get, sigma, unit, scale in rows:
        shown = "" if nominal is None else f"{get(nominal) * scale:.6g}"
        old = "no body" if before is None else f"{get(before) * scale:.6g}"
        new = "no body" if after is None else f"{get(after) * scale:.6g}"
        table.add_row(name, old, new, "" if std is None else f"{sigma(std) * scale:.2g}", shown, unit)
    return table


def print_screens(console: Console, screens: dict, sensors: list[str]) -> None:
    """The model-free screens in a line or two."""
    if screens["channel_consistency"] is not None:
        worst = np.argsort(screens["channel_consistency"])[::-1][:3]
        listed = ", ".join(f"{sensors[k]} ({screens['channel_consistency'][k]:.1%})" for k in worst)
        console.print(f"model-free: channels farthest from the others' rigid motion (LOCO misfit): {listed}")
    if screens["negative_driving_points"]:
        console.print(f"model-free: driving points with a non-positive massline: {screens['negative_driving_points']}")


def document(result: Diagnosis, recording, zones, found, planar: bool, screens: dict) -> dict:
    """DESIGN.md's diagnose JSON (and the per-channel fit and screens)."""
    before, after = result.estimates[0].body, result.corrected
    return {
        "findings": [finding_payload(x, recording) for x in result.findings],
        "fit": {"before": result.relative_rms("before"), "after": result.relative_rms("after"), "noise": result.noise},
        "fit_per_channel": {
            "before": result.relative_rms("before", axis=1).tolist(),
            "after": result.relative_rms("after", axis=1).tolist(),
        },
        "properties": {
            "before": None
            if before is None
            else payload(before, property_std(result.estimates[0]), (found.low, found.high), planar),
            "after": None
            if after is None
            else payload(after, property_std(result.estimates[1]), (found.low, found.high), planar),
        },
        "band_hz": [zones.low, zones.high],
        "screens": screens,
    }


@dataclass(frozen=True, eq=False)
class DiagnosisRun:
    """A diagnosis of a recording with what it was run on: the bands, the layout, the channel names, the screens."""

    recording: Recording
    zones: Zones
    found: Zones
    band: BandData
    layout: Layout
    planar: bool
    sensors: list[str]
    hits: list[str]
    noise: float
    screens: dict
    result: Diagnosis

    def off_rigid(self) -> np.ndarray | None:
        """How far each recorded channel sits from the rigid motions at every band line (None without redundancy)."""
        if not roomy(self.layout):
            return None
        S = kinematic_matrix(self.layout.sensors, self.layout.planar)
        return np.linalg.norm(rigid_subspace_residual(self.band.frf, S), axis=1)


def diagnose_recording(recording: Recording, band=None, nominal=None, transverse: float = TRANSVERSE) -> DiagnosisRun:
    """The diagnosis on ``band`` (lo, hi) Hz, the plan's, or the found one; properties on identify's band."""
    f = recording.frequencies
    zones = given_band(f, *band) if band else find_band(f, recording.frf)
    found = estimation_band(f, recording.frf, zones)
    data = BandData.from_recording(f, recording.frf, zones.low, zones.high)
    wide = BandData.from_recording(f, recording.frf, found.low, found.high)
    empty = np.zeros((len(recording.sensors), len(recording.exciters)))
    planar = is_planar(Masslines(empty, recording.sensors, recording.exciters))
    layout = Layout.of(recording.sensors, recording.exciters, planar)
    sensors, hits = labels(recording)
    screens = screen(data, layout)
    result = diagnose(data, layout, nominal, transverse, wide)
    return DiagnosisRun(
        recording, zones, found, data, layout, planar, sensors, hits, relative_noise(data), screens, result
    )


def run(args: argparse.Namespace, console: Console) -> None:
    for path in (args.json, args.plot, args.report):
        if path:
            claim_output(path, args.force)
    mesh = nominal_mesh(args)
    nominal = None if mesh is None else mesh.nominal
    recording = to_recording(read_uff(args.uff))
    with console.status("diagnosing: discrete faults, then the effect library one at a time"):
        found = diagnose_recording(recording, args.band, nominal, args.transverse)
    zones, band, noise, result, sensors = found.zones, found.band, found.noise, found.result, found.sensors
    console.print(
        f"band {zones.low:.1f}–{zones.high:.1f} Hz ({zones.rule}), {len(band.frequencies)} lines × "
        f"{band.frf.shape[0]}×{band.frf.shape[1]} FRFs; noise {noise:.2%} of the FRFs (RMS)"
    )
    if not roomy(found.layout):
        console.print(
            f"[yellow]note:[/] {len(found.layout.sensors)} sensor channels leave no redundancy: a faulty channel "
            "cannot be told from the body's properties (diagnosis needs at least 8 channels, 5 for a plate)"
        )
    print_screens(console, found.screens, sensors)
    before, after = result.relative_rms("before"), result.relative_rms("after")
    if not result.findings:
        console.print(f"no findings: the rigid body fits every line within the noise ({before / noise:.2f}× it)")
    for k, finding in enumerate(result.findings, 1):
        console.print(f"{k}. {finding_note(finding, sensors, found.hits)}")
    console.print(
        f"fit: relative RMS residual {before:.2%} before, {after:.2%} after "
        f"({before / noise:.2f}× → {after / noise:.2f}× the noise)"
    )
    console.print(properties_table(result, nominal))
    if args.plot:
        write_atomic_bytes(
            args.plot, diagnosis_figure(result, band, sensors, found.hits, found.off_rigid()), args.force
        )
        console.print(f"wrote {args.plot}")
    if args.json:
        doc = document(result, recording, zones, found.found, found.planar, found.screens)
        write_atomic(args.json, to_json(doc), args.force)
        console.print(f"wrote {args.json}")
    if args.report:
        from massline.reports.diagnosis_report import diagnose_report

        write_report(console, args.report, lambda: diagnose_report(found, args.uff, mesh), args.force)
