"""The default plan against the paper's minimal one on the bundled bodies: the table of them in docs/validation.md.

    python benchmarks/default_plans.py [--bodies NAME ...]

Each plan runs through the command line as a user runs it (`massline plan BODY --out DIR`, and `--minimal`),
so the figures are those of the plans a user gets: 400 candidates, seed 0, mountable points slid on their faces.
The table prints as docs/validation.md shows it: the layout (lines × hits), the worst predicted relative 1-σ
(mass, CoG against the radius of gyration, principal moments) and log det F. Everything in it is deterministic.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np
from common import layout, planned

from massline.core.accuracy import worst_relative_std
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody
from massline.meshes import BUNDLED


def figures(doc: dict) -> tuple[str, float, float]:
    """The layout, its worst relative 1-σ and log det F, from plan.json."""
    nominal = doc["nominal"]
    body = RigidBody(nominal["mass"], np.array(nominal["cog"]), np.array(nominal["inertia_cog"]))
    std = {k: np.asarray(v, dtype=float) for k, v in doc["predicted_std"].items()}
    worst = worst_relative_std(RigidModel(body, doc["planar"]), std)
    return layout(doc), worst, doc["criterion"]["log_det"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", choices=list(BUNDLED), default=["plate", "structure", "bracket"])
    args = parser.parse_args()
    print("| body | default plan | worst relative 1-σ | log det F | minimal plan | worst relative 1-σ | log det F |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.bodies:
            default = figures(planned([name], Path(scratch) / f"{name}-default"))
            minimal = figures(planned([name, "--minimal"], Path(scratch) / f"{name}-minimal"))
            cells = [f"{layout} | {worst:.2%} | {log_det:.1f}" for layout, worst, log_det in (default, minimal)]
            print(f"| {name} | {cells[0].replace('%', ' %')} | {cells[1].replace('%', ' %')} |", flush=True)


if __name__ == "__main__":
    main()
