"""The recording's noise against the simulated noise, and every fit against that noise: docs/identifying.md's table.

    python benchmarks/recording_noise.py [--bodies plate,bracket,structure] [--seeds 3] [--effects A,B]
        [--no-diagnose] [--jobs 2] [--out DIR]

Each case is what a user runs: ``massline plan BODY`` (the default plan), ``massline simulate`` with 1 % noise
(the lab's file: 0 Hz line, coherence, the plan's cord) clean or with one effect of the registry concealed at a
line the seed draws (the blind suite's sizes: benchmarks/diagnose_blind.py), then identify and diagnose (with the
mesh's body). Per case: the noise identify states over its band (the coherence's), the line differences' over the
same band (the route a file without coherence takes), identify's band fit and the diagnosis's fit after, each
over the noise. The table gives, per effect, n and the worst of each over the bodies and seeds.
"""

from __future__ import annotations

import argparse
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from common import massline
from diagnose_blind import FAULTS, planned, swapped

from massline.core.errors import MasslineError
from massline.identify.diagnose.effects import simulated
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import identify_recording
from massline.meshes import BUNDLED
from massline.meshes.loader import load_body

NOISE = 0.01  # simulate's default relative noise
SIZES = {**{name: size for name, (size, _) in FAULTS.items()}, "transverse_sensitivity": "0.03",
         "mains_interference": "0.1"}  # fmt: skip


def effect_options(effect: str | None, plan: Path, seed: int) -> list[str]:
    """simulate's options concealing ``effect`` (None: clean)."""
    if effect is None:
        return []
    if effect == "excitation_mass_loading":
        return ["--gauge-mass", SIZES[effect]]
    if effect == "channel_swap":
        return ["--effect", "channel_swap@" + ",".join(map(str, swapped(plan, seed)))]
    return ["--effect", f"{effect}={SIZES[effect]}" if SIZES[effect] else effect]


def case(plan: Path, effect: str | None, seed: int, diagnosed: bool) -> dict:
    """One virtual test: identify's noise and fit, the line differences', and the diagnosis's fit after."""
    path = plan.parent.parent / f"{plan.parent.name}-{effect or 'clean'}-{seed}.uff"
    massline("simulate", str(plan), "--seed", str(seed), "--out", str(path), "--force",
             *effect_options(effect, plan, seed))  # fmt: skip
    row = {"effect": effect or "clean", "identify": np.nan, "diagnose": np.nan}
    try:
        noise = identify_recording(path, draws=0).payload["noise"]
        row["identify"] = noise["fit_over_noise"]
    except MasslineError:  # identify refuses a flipped or swapped channel: the diagnosis's band and noise
        diagnosed, noise = True, None
    if diagnosed:
        body = plan.parent.name.removeprefix("plan-")
        nominal = load_body(BUNDLED[body].path, "m", BUNDLED[body].density).nominal
        run = diagnose_recording(path, None, nominal)
        row["diagnose"] = run.result.relative_rms("after") / run.result.noise
        noise = noise or run.noise.payload
    row |= {"noise": noise["relative"] / NOISE, "differences": noise["line_differences"] / NOISE,
            "method": noise["method"]}  # fmt: skip
    return row


def table(rows: list[dict]) -> None:
    """Per effect: n, the range of noise / simulated over the coherence and the line differences, and the least
    fit / noise of identify and of the diagnosis."""
    print("| file | n | noise / simulated (coherence) | line differences / simulated | identify's fit / noise, least"
          " | diagnosis's fit after / noise, least |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for effect in dict.fromkeys(r["effect"] for r in rows):
        mine = [r for r in rows if r["effect"] == effect]
        span = lambda key: f"{min(r[key] for r in mine):.3f}–{max(r[key] for r in mine):.3f}"  # noqa: E731
        least = lambda key: f"{np.nanmin([r[key] for r in mine]):.2f}" if any(np.isfinite(r[key]) for r in mine) else "–"  # noqa: E731, E501
        print(f"| {effect} | {len(mine)} | {span('noise')} | {span('differences')} | {least('identify')} |"
              f" {least('diagnose')} |")  # fmt: skip
    every = lambda key: np.array([r[key] for r in rows])  # noqa: E731
    within = np.mean(np.abs(every("noise") - 1) < 0.2), np.mean(np.abs(every("differences") - 1) < 0.2)
    fits = np.concatenate([every("identify"), every("diagnose")])
    fits = fits[np.isfinite(fits)]
    print(f"\n{len(rows)} files: noise within 20 % of the simulated in {within[0]:.0%} (coherence) and "
          f"{within[1]:.0%} (line differences); {np.sum(fits < 0.8)} of {len(fits)} fits below 0.8× the noise "
          f"(least {fits.min():.2f}×); methods: {sorted(set(r['method'] for r in rows))}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="plate,bracket,structure")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--no-diagnose", action="store_true", help="identify only (no diagnosis's fit)")
    parser.add_argument("--effects", default=None, help="the effects to conceal, comma-separated (default: clean and "
                        "every one simulate conceals; 'clean' for none)")  # fmt: skip
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--out", type=Path, default=None, help="keep the plans and files here")
    args = parser.parse_args()
    every = [None] + [cls.name for cls in simulated()]
    chosen = None if args.effects is None else args.effects.split(",")
    effects = [e for e in every if chosen is None or (e or "clean") in chosen]
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.out or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        plans = [planned(body, folder) for body in args.bodies.split(",")]
        work = [(plan, effect, seed, not args.no_diagnose) for effect in effects for plan in plans
                for seed in range(args.seeds)]  # fmt: skip
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(case, *zip(*work)))
    table(rows)


if __name__ == "__main__":
    main()
