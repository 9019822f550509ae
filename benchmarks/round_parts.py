"""Plans on round parts: the table of them in docs/validation.md (turned parts, whose normals all meet the axis).

    python benchmarks/round_parts.py [--parts NAME ...] [--sections N ...] [--kinds KIND ...] [--virtual]

Each part (``massline.meshes.round_parts``: a stepped shaft, a cylinder, a hollow cylinder, a filleted box; steel)
is written as an STL of ``sections`` facets around a circle and planned through the command line as a user plans
it: the default (the cheapest diagnosable), ``--minimal`` and ``--triaxial 3``. Per plan: the layout (lines × hits,
those on mounting blocks), whether it is diagnosable, the worst predicted relative 1-σ and that of the smallest
principal moment (a shaft's axial one), the least distance of a point from a sharp edge against its clearance, the
largest gap under an accelerometer's base, and the seconds the plan took. ``--virtual`` also simulates each plan
(``massline simulate``, its defaults) and identifies the recording (``massline identify``): the smallest principal
moment's error in units of its identified 1-σ. Deterministic but for the seconds.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from common import run_plan
from default_plans import figures as layout_figures

from massline.meshes.round_parts import PARTS, STEEL
from massline.placement.mountable import PAD_GAP, feature_edges, foot_on_segments

KINDS = {"default": [], "minimal": ["--minimal"], "triaxial": ["--triaxial", "3"]}


def edge_distance(mesh, points: np.ndarray) -> np.ndarray:
    """Each point's distance (m) from the nearest sharp edge of ``mesh`` (inf where it has none)."""
    edges = feature_edges(mesh)
    if not len(edges):
        return np.full(len(points), np.inf)
    a = np.repeat(edges[None, :, 0], len(points), axis=0).reshape(-1, 3)
    b = np.repeat(edges[None, :, 1], len(points), axis=0).reshape(-1, 3)
    p = np.repeat(points, len(edges), axis=0)
    return np.linalg.norm(p - foot_on_segments(p, a, b), axis=1).reshape(len(points), -1).min(axis=1)


def smallest_moment(doc: dict) -> tuple[int, float]:
    """Index and relative predicted 1-σ of the smallest principal moment in plan.json."""
    moments = np.asarray(doc["nominal"]["principal_moments"])
    k = int(np.argmin(moments))
    return k, float(doc["predicted_std"]["principal_moments"][k] / moments[k])


def figures(mesh, doc: dict) -> dict:
    """What the table prints of one plan.json."""
    lines = doc["sensors"] + doc["exciters"]
    points = np.array([line["point"] for line in lines])
    clearance = np.array([doc["mounting"]["sensor_clearance_m"]] * len(doc["sensors"])
                         + [doc["mounting"]["hit_clearance_m"]] * len(doc["exciters"]))  # fmt: skip
    kinds = [line["mount"]["kind"] for line in lines]
    gaps = [line["mount"]["gap_m"] for line in doc["sensors"] if line["triaxial"] is None]
    _, axial = smallest_moment(doc)
    return {
        "layout": f"{len(doc['sensors'])} × {len(doc['exciters'])}",
        "blocks": f"{kinds[: len(doc['sensors'])].count('block')} + {kinds[len(doc['sensors']):].count('block')}",
        "diagnosable": doc["diagnosability"]["diagnosable"],
        "worst": layout_figures(doc)[1],
        "axial": axial,
        "edge_margin": float((edge_distance(mesh, points) - clearance).min()),
        "gap": max(gaps, default=0.0),
    }


def virtual(plan: Path, folder: Path) -> float:
    """The smallest principal moment's identified error over its 1-σ, from a virtual test of ``plan``."""
    massline = str(Path(sys.executable).with_name("massline"))
    recording, result = folder / "test.uff", folder / "identified.json"
    commands = (["simulate", str(plan), "--out", str(recording)], ["identify", str(recording), "--json", str(result)])
    for command in commands:
        subprocess.run([massline, *command, "--force"], capture_output=True, text=True, check=True)
    doc, found = json.loads(plan.read_text()), json.loads(result.read_text())
    k, _ = smallest_moment(doc)
    truth = np.sort(doc["nominal"]["principal_moments"])[0]
    moments, std = np.asarray(found["principal_moments"]), np.asarray(found["std"]["principal_moments"])
    j = int(np.argmin(moments))
    return float((moments[j] - truth) / std[j])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", nargs="+", default=list(PARTS), choices=list(PARTS))
    parser.add_argument("--sections", nargs="+", type=int, default=[16, 32, 128])
    parser.add_argument("--kinds", nargs="+", default=list(KINDS), choices=list(KINDS))
    parser.add_argument("--virtual", action="store_true", help="simulate and identify each plan")
    args = parser.parse_args(argv)
    print("| part | sections | plan | lines × hits | on blocks (lines + hits) | diagnosable | worst 1-σ | "
          "smallest moment 1-σ | edge margin (mm) | largest gap (mm) | seconds |" + (" z |" if args.virtual else ""))
    print("|---" * (11 + args.virtual) + "|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.parts:
            for sections in args.sections:
                mesh = PARTS[name](sections)
                stl = Path(tmp) / f"{name.replace(' ', '_')}_{sections}.stl"
                mesh.export(stl)
                for kind in args.kinds:
                    out = Path(tmp) / f"{stl.stem}_{kind}"
                    run, seconds = run_plan([str(stl), "--units", "m", "--density", str(STEEL), *KINDS[kind]], out)
                    if run.returncode != 0:
                        print(f"| {name} | {sections} | {kind} | refused: {run.stderr.strip()} |", flush=True)
                        continue
                    doc = json.loads((out / "plan.json").read_text())
                    f = figures(mesh, doc)
                    z = f" {virtual(out / 'plan.json', out):+.2f} |" if args.virtual else ""
                    print(
                        f"| {name} | {sections} | {kind} | {f['layout']} | {f['blocks']} | "
                        f"{'yes' if f['diagnosable'] else 'no'} | {f['worst']:.2%} | {f['axial']:.2%} | "
                        f"{f['edge_margin'] * 1e3:+.2f} | {f['gap'] * 1e3:.2f} | {seconds:.0f} |{z}",
                        flush=True,
                    )
    print(f"(edge margin: distance from the nearest sharp edge minus the clearance, ≥ 0; gap ≤ {PAD_GAP * 1e3:g} mm)")


if __name__ == "__main__":
    main()
