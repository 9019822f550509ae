"""Is identify's ± the error it makes, and does the plan predict that ±? The uncertainty budget, measured.

For each bundled body (bracket, plate, structure) and each of its plans (``--minimal`` and the default), SEEDS
default virtual tests (``massline simulate``'s default: the chain's errors drawn from the budget's 1-σ, noise
1 %) are identified (``massline identify``'s defaults, the plan's housings taken off). For mass, each CoG component
and each principal moment it prints:

* RMS z: the RMS over the seeds of (identified − true) / reported 1-σ (1 when the ± is the error's size; the
  issue asks 0.75–1.33);
* identify's reported 1-σ (median over the seeds) and the plan's predicted 1-σ (plan.json's ``predicted_std``,
  the same budget before the test) and their ratio (within 25 % asked).

Then, on the exporters' files of tests/fixtures/uff (other software's), whether any reported 1-σ of the mass or a
principal moment falls below the force transducer's calibration floor (1 % of the value), with the default
calibration and with ``--calibration 0``.

    python benchmarks/uncertainty_budget.py [--seeds 20] [--bodies bracket plate structure] [--work DIR]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from common import planned

from massline.core.calibration import Calibration
from massline.core.errors import MasslineError
from massline.core.properties import reported_values
from massline.core.rigid_body import RigidBody
from massline.identify.pipeline import identify_recording
from massline.placement.plan_file import read_plan
from massline.virtual.acquisition import Acquisition
from massline.virtual.housing_loading import planned_masses
from massline.virtual.planned_test import plan_mesh
from massline.virtual.simulation import simulate_test

FIXTURES = Path(__file__).resolve().parent.parent / "tests" / "fixtures" / "uff"
NAMES = ["mass", "CoG x", "CoG y", "CoG z", "moment 1", "moment 2", "moment 3"]


def entries(values: dict) -> np.ndarray:
    """mass, CoG (3), principal moments (3) of identify's value or std keys."""
    return np.concatenate([[values["mass"]], values["cog"], values["principal_moments"]]).astype(float)


def truth_entries(truth: dict, planar: bool) -> np.ndarray:
    """The same of the true bare body (the truth file's ``nominal``), a plate's in-plane moments for plate data."""
    nominal = truth["nominal"]
    body = RigidBody(nominal["mass"], np.array(nominal["cog"]), np.array(nominal["inertia_cog"]))
    return entries(reported_values(body, planar))


def one_plan(body: str, minimal: bool, seeds: int, work: Path) -> dict:
    """z of every seed, identify's reported 1-σ and the plan's predicted 1-σ of one body's plan."""
    name = f"{body}-{'minimal' if minimal else 'default'}"
    folder = work / name
    if not (folder / "plan.json").exists():
        planned([body] + (["--minimal"] if minimal else []), folder)
    sensors, exciters, doc = read_plan(folder / "plan.json")
    mesh = plan_mesh(doc, folder / "plan.json")
    housings = planned_masses(doc)
    z, reported = [], []
    for seed in range(1, seeds + 1):
        acquisition = Acquisition(sensor_mass=housings, chain=Calibration())
        test = simulate_test(doc, sensors, exciters, mesh, acquisition=acquisition, seed=seed)
        found = identify_recording(test.recording, sensor_mass=housings)
        payload = found.payload
        values, std = entries(payload), entries(payload["std"])
        z.append((values - truth_entries(test.truth, found.planar)) / std)
        reported.append(std)
    predicted = doc.get("predicted_std")
    return {
        "name": name,
        "layout": f"{len(sensors)} × {len(exciters)}",
        "z": np.array(z),
        "reported": np.median(reported, axis=0),
        "predicted": None if predicted is None else entries(predicted),
    }


def rms(z: np.ndarray) -> np.ndarray:
    """The RMS of each column over its finite entries (nan for a column with none: a plate's z_G)."""
    finite = np.isfinite(z)
    mean_square = np.sum(np.where(finite, z, 0.0) ** 2, axis=0) / np.fmax(finite.sum(axis=0), 1)
    return np.where(finite.any(axis=0), np.sqrt(mean_square), np.nan)


def print_plan(result: dict) -> None:
    z = result["z"]
    rms_z = rms(z)
    print(f"\n{result['name']} ({result['layout']}), {len(z)} seeds")
    print(f"{'':10}" + "".join(f"{n:>11}" for n in NAMES))
    print(f"{'RMS z':10}" + "".join(f"{v:11.2f}" for v in rms_z))
    print(f"{'reported':10}" + "".join(f"{v:11.3g}" for v in result["reported"]))
    if result["predicted"] is not None:
        print(f"{'predicted':10}" + "".join(f"{v:11.3g}" for v in result["predicted"]))
        ratio = result["predicted"] / result["reported"]
        print(f"{'pred/rep':10}" + "".join(f"{v:11.2f}" for v in ratio))


def fixture_floors() -> None:
    """The exporters' files: the smallest reported 1-σ of the mass and of a principal moment, relative."""
    print("\nexporters' fixtures: smallest relative 1-σ of the mass and the principal moments (floor 1 %)")
    for path in sorted(FIXTURES.glob("*")):
        if path.suffix.lower() not in (".uff", ".unv") or path.name.startswith("."):
            continue
        row = [path.name]
        for calibration in (None, Calibration(0.0, 0.0)):
            try:
                found = identify_recording(path, calibration=calibration, draws=0)
            except MasslineError as error:  # a file identify refuses (no FRFs, no geometry): said, not counted
                row.append("refused: " + str(error).replace(f"file {path}", "the file")[:90])
                continue
            p = found.payload
            moments = np.divide(p["std"]["principal_moments"], np.abs(p["principal_moments"]))
            relative = np.concatenate([[p["std"]["mass"] / p["mass"]], moments])
            row.append(f"{100 * np.nanmin(relative):.3g} %")
        print(f"  {row[0]:<38} default: {row[1]}; --calibration 0: {row[2]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--bodies", nargs="+", default=["bracket", "plate", "structure"])
    parser.add_argument("--plans", nargs="+", default=["minimal", "default"])
    parser.add_argument("--work", type=Path, help="where the plans are kept (default: a temporary folder)")
    parser.add_argument("--no-fixtures", action="store_true")
    args = parser.parse_args()
    work = args.work or Path(tempfile.mkdtemp(prefix="massline-budget-"))
    summary = []
    for body in args.bodies:
        for plan in args.plans:
            result = one_plan(body, plan == "minimal", args.seeds, work)
            print_plan(result)
            summary.append(result)
    all_z = np.concatenate([r["z"] for r in summary])
    print(f"\nall: RMS z per property over {len(all_z)} tests: " + ", ".join(
        f"{n} {v:.2f}" for n, v in zip(NAMES, rms(all_z))))
    if not args.no_fixtures:
        fixture_floors()


if __name__ == "__main__":
    main()
