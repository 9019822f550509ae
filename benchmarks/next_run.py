"""The next run from the first, checked by simulation: for each seed, a virtual first run of a body's minimal plan
(1 % noise, rigid), ``massline plan BODY --after FIRST --additions N``, the second run it plans simulated on the
first run's support, and both runs identified together over the first run's band. Prints, per seed, the target,
its 1-σ after the first run, the plan's prediction after both, the merged identification's 1-σ from the
estimator's information (what the plan predicts) and its reported 1-σ (scaled by √χ²_red where that is above 1,
the tails' truncation added: neither is predicted), the reduced χ², and the ratio of information to prediction; then the same for the best of ``--random``
random additions of the proposal's shape (predicted, not simulated).

    python benchmarks/next_run.py [--body bracket] [--seeds 1 2 3] [--additions 1] [--random 20]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.identify.measured_layout import measured_layout
from massline.identify.pipeline import identify_recording
from massline.meshes import BUNDLED
from massline.meshes.loader import load_body
from massline.placement.candidates import CandidateOptions, candidate_lines, candidate_points
from massline.core.accuracy import property_jacobian
from massline.placement.next_run import TARGETS, Measured, Runs, target_std
from massline.placement.on_surface import is_plate


def massline(*args) -> None:
    done = subprocess.run([sys.executable, "-m", "massline", *map(str, args)], capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(done.stderr)


def random_best(runs: Runs, index: int, shape: tuple[int, int], sides: tuple[Lines, Lines], draws: int, seed: int):
    """The least predicted 1-σ of property ``index`` among ``draws`` random additions of ``shape``."""
    rng, first, best = np.random.default_rng(seed), runs.first, np.inf
    for _ in range(draws):
        S = first.sensors + sides[0][rng.choice(len(sides[0]), shape[0], replace=False)]
        E = first.exciters + sides[1][rng.choice(len(sides[1]), shape[1], replace=False)]
        best = min(best, target_std(runs.model, runs.information(S, E), index))
    return best


def one_seed(body_name: str, seed: int, additions: int, draws: int, folder: Path) -> dict:
    plan = folder / "minimal"
    massline("plan", body_name, "--minimal", "--out", plan, "--force")
    first, after = folder / f"first{seed}.uff", folder / f"after{seed}"
    rigid = ("--rigid", "--nodes", "2411")
    massline("simulate", plan / "plan.json", *rigid, "--seed", seed, "--out", first, "--force")
    massline("plan", body_name, "--after", first, "--additions", additions, "--out", after, "--force")
    doc, planned = json.loads((after / "plan.json").read_text()), json.loads((plan / "plan.json").read_text())
    second = folder / f"second{seed}.json"
    second.write_text(json.dumps(doc | {k: planned[k] for k in ("suspension", "band", "elastic")}))
    massline("simulate", second, *rigid, "--seed", 1000 + seed, "--out", folder / f"second{seed}.uff", "--force")
    target, scale = doc["after"]["target"], 1e3 if doc["after"]["target"].startswith("cog") else 1.0
    found = identify_recording([first, folder / f"second{seed}.uff"], doc["after"]["band_hz"])
    j = property_jacobian(found.best.model)[TARGETS[target]]
    information = j @ found.best.covariance @ j / max(found.best.chi2, 1.0)  # the scaling by χ²_red undone
    statistical = scale * float(np.sqrt(information))
    reported = {"mass": found.std["mass"], **{f"cog_{a}": found.std["cog"][k] for k, a in enumerate("xyz")},
                **{f"J{k + 1}": found.std["principal_moments"][k] for k in range(3)}}.get(target, np.nan)  # fmt: skip
    best = doc["after"]["proposals"][0]
    bundled = BUNDLED[body_name]
    body = load_body(bundled.path, "m", bundled.density, None)
    model = RigidModel(body.nominal, is_plate(body))
    layout = measured_layout(first)
    measured = Measured(sensors=layout.recording.sensors, exciters=layout.recording.exciters,
                        magnitude=layout.magnitude, sigma=layout.sigma, transverse=layout.transverse)  # fmt: skip
    runs = Runs(model=model, first=measured, noise=measured.noise(model.nominal.mass))
    sides = candidate_lines(candidate_points(body.mesh, CandidateOptions()), False, model.planar, False)
    shape = (len(best["sensors"]), len(best["exciters"]))
    randomly = scale * random_best(runs, TARGETS[target], shape, (sides[0].lines, sides[1].lines), draws, seed)
    return {
        "seed": seed, "target": target, "addition": best["what"], "before": doc["after"]["std_before"],
        "predicted": best["std_after"], "statistical": statistical, "reported": scale * reported,
        "ratio": statistical / best["std_after"], "random_best": randomly, "chi2": found.best.chi2,
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--body", default="bracket", choices=sorted(BUNDLED))
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--additions", type=int, default=1, choices=(1, 2, 3))
    parser.add_argument("--random", type=int, default=20)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        rows = [one_seed(args.body, s, args.additions, args.random, Path(folder)) for s in args.seeds]
    print("seed  target  addition            1-σ first  predicted  merged info  merged reported  χ²_red  ratio  "
          "best random")
    for r in rows:
        print(f"{r['seed']:4d}  {r['target']:6s}  {r['addition']:18s}  {r['before']:9.3g}  {r['predicted']:9.3g}  "
              f"{r['statistical']:11.3g}  {r['reported']:15.3g}  {r['chi2']:6.2f}  {r['ratio']:5.2f}  {r['random_best']:11.3g}")  # fmt: skip
    ratios = np.array([r["ratio"] for r in rows])
    print(f"information / predicted: {ratios.min():.2f}–{ratios.max():.2f} over {len(rows)} seeds; "
          f"proposal below the best of {args.random} random additions in "
          f"{sum(r['predicted'] < r['random_best'] for r in rows)} of {len(rows)}")  # fmt: skip


if __name__ == "__main__":
    main()
