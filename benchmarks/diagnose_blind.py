"""The diagnosis, blind, on the bundled bodies' default plans: false alarms, misses, and what it says outside its library.

Each case is what a user runs: ``massline plan BODY`` (the default, diagnosable plan), ``massline simulate``
(the lab's file: exporter's units, 0 Hz line, coherence, the default cord; or foam, or hammer hits) with one
fault concealed at a random line, then ``diagnose`` with the mesh's body. Each case's outcome is the first
fault named (effect and channel or hit), ``unexplained`` at the place it locates, or nothing.

    python benchmarks/diagnose_blind.py [--bodies bracket,plate] [--seeds 2] [--first-seed 0] [--faults A,B]
        [--without EFFECT] [--no-clean] [--jobs 2] [--out DIR]

``--faults ''`` runs the clean files alone: the false-alarm rate, over as many seeds as it needs.

``--without EFFECT`` takes the effect out of the diagnosis's registry (the simulator still conceals it): the
files carrying it should get ``unexplained`` at the right place, not a wrong name (the leave-one-effect-out
check). A test-physics effect (``suspension``, ``residual_flexibility``: the search's tail laws;
``mains_interference``: the lines set aside) is left out with ``--faults ''``: every clean file carries the
support and the elastic modes, the hum files the hum, and none should get a fault named.
``mixed_housings`` is a fault of the test as a whole: 25 g housings at nodes 1 and 2, 8 g elsewhere, none given
to the diagnosis (``sensor_mass_loading`` at the heavy channels, with the mesh). The table prints n per cell; the
rates are over the cases run.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from collections import Counter
from pathlib import Path

import numpy as np
from common import massline

import massline.identify.diagnose.effects as registry
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.meshes import BUNDLED
from massline.meshes.loader import load_body

# sizes at the smallest faults the diagnosis should name (5 % / 5° / 5 mm / 10 g) and above
FAULTS = {  # name: (--effect SIZE, place kind)
    "sensor_gain": ("-0.1", "sensor"),
    "sensor_polarity": ("", "sensor"),
    "sensor_direction": ("8", "sensor"),
    "sensor_location": ("0.008", "sensor"),
    "sensor_mass_loading": ("0.01", "sensor"),
    "excitation_direction": ("8", "hit"),
    "excitation_location": ("0.008", "hit"),
    "channel_swap": ("", "sensor"),  # two channels' labels exchanged, the pair drawn from the seed
    "excitation_mass_loading": ("0.02", "drive"),  # a shaker test with 20 g gauges (--gauge-mass): every column
    "mixed_housings": ("0.008 1=0.025 2=0.025", "housings"),  # --sensor-mass: 25 g at nodes 1 and 2, 8 g elsewhere
}
LABELS = {  # docs/validation.md's name of each concealed fault
    "sensor_gain": "10 % gain",
    "sensor_polarity": "polarity",
    "sensor_direction": "8° sensor tilt",
    "sensor_location": "8 mm sensor offset",
    "sensor_mass_loading": "10 g housing",
    "channel_swap": "two channels swapped",
    "excitation_direction": "8° hit tilt",
    "excitation_location": "8 mm hit offset",
    "excitation_mass_loading": "20 g force gauge at every drive point",
    "mixed_housings": "25 g housings at points 1 and 2, 8 g elsewhere",
}
NAMED = {"mixed_housings": "sensor_mass_loading"}  # the effect a concealed fault is named as, where not its own
CLEAN = {  # the conditions clean files are run under (the faulty ones: the plan's soft cord)
    "cord": [],
    "foam": ["--suspension", "foam"],
    "impact": ["--impact"],
    "mains": ["--effect", "mains_interference=0.1"],
    "stiff": "stiff",  # a cord whose bounce is a tenth of the first elastic mode (stiff_cord)
}


def stiff_cord(plan: Path) -> list:
    """--suspension for a cord above the CoG whose bounce is f₁/10: k = m (2π f₁/10)²."""
    doc = json.loads(plan.read_text())
    mass, cog = doc["nominal"]["mass"], doc["nominal"]["cog"]
    k = mass * (2 * np.pi * doc["elastic"]["frequencies_hz"][0] / 10) ** 2
    at = ";".join(f"{v:.6g}" for v in (cog[0], cog[1], cog[2] + 0.02))
    return ["--suspension", f"cord:k={k:.6g},L=1,at={at}"]


def planned(body: str, folder: Path) -> Path:
    """The body's default plan (planned once per folder)."""
    plan = folder / f"plan-{body}" / "plan.json"  # not a folder named as the body: it would shadow the bundled name
    if not plan.exists():
        massline("plan", body, "--out", str(plan.parent), "--force")
    return plan


def case(plan: Path, fault: str | None, seed: int, extra: list, folder: Path) -> dict:
    """Simulate one case, diagnose it with the mesh's body; its outcome."""
    style = extra if isinstance(extra, str) else "-".join(extra).replace("=", "").replace(":", "") or "cord"
    path = folder / f"{plan.parent.name}-{fault or 'clean'}-{seed}-{style}.uff"
    effect = []
    if fault == "excitation_mass_loading":
        effect = ["--gauge-mass", FAULTS[fault][0]]
    elif fault == "mixed_housings":
        effect = ["--sensor-mass", *FAULTS[fault][0].split()]
    elif fault == "channel_swap":
        effect = ["--effect", "channel_swap@" + ",".join(map(str, swapped(plan, seed)))]
    elif fault:
        size, _ = FAULTS[fault]
        effect = ["--effect", f"{fault}={size}" if size else fault]
    extra = stiff_cord(plan) if extra == "stiff" else extra
    massline("simulate", str(plan), "--seed", str(seed), "--out", str(path), "--force", *effect, *extra)
    truth = json.loads(path.with_suffix(".truth.json").read_text())
    body = plan.parent.name.removeprefix("plan-")
    mesh = load_body(BUNDLED[body].path, "m", BUNDLED[body].density)
    start = time.perf_counter()
    found = diagnose_recording(path, None, mesh.nominal)
    seconds = time.perf_counter() - start
    return {"body": body, "seed": seed, "fault": fault or "none", "condition": style, "truth": truth,
            "heavy": heavy(plan),
            "outcome": outcome(found), "seconds": seconds, "before": found.chi2["before"], "after": found.chi2["after"],
            "worse": worse(found, mesh.nominal)}  # fmt: skip


def swapped(plan: Path, seed: int) -> list[int]:
    """Two of the plan's channels (1-based) drawn from ``seed``: the swap concealed."""
    channels = len(json.loads(plan.read_text())["sensors"])  # one entry per channel, a triaxial's three too
    return sorted(int(c) + 1 for c in np.random.default_rng(seed).choice(channels, 2, replace=False))


def heavy(plan: Path) -> list[int]:
    """The channels (1-based) whose housings ``mixed_housings`` makes 25 g: those at nodes 1 and 2."""
    return [i + 1 for i, s in enumerate(json.loads(plan.read_text())["sensors"]) if s["node"] in (1, 2)]


def worse(found, bare) -> float:
    """How much further the body after is from the bare body than identify's before, in identify's 1-σ: the
    largest over the mass and the CoG's components (nan when identify refused the file)."""
    if found.before is None or found.after_body is None:
        return float("nan")
    std = found.before.std

    def error(body):
        return np.abs(np.concatenate([[body.mass - bare.mass], body.cog - bare.cog]))

    sigma = np.concatenate([[std["mass"]], std["cog"]])
    return float(np.max((error(found.after_body) - error(found.before.body)) / sigma))


def outcome(found) -> tuple:
    """(kind, effect, sensor channels 1-based, hits 1-based) of the first fault named, else the unexplained, else none."""
    first = [f for f in found.findings if f.kind == "fault"] or [f for f in found.findings if f.kind == "unexplained"]
    if not first:
        return ("none", "", (), ())
    f = first[0]
    hits = tuple(j + 1 for j in f.parameters.get("hits", []))
    hits += () if f.exciter is None else (f.exciter + 1,)
    return (f.kind, f.effect, tuple(c + 1 for c in f.channels), hits)


def placed(row: dict) -> bool:
    """Whether the outcome's place is the concealed fault's (any of its lines; a gauge's: every drive point, a
    misfit found anywhere on the excitation side, or spread)."""
    kind, effect, channels, hits = row["outcome"]
    if FAULTS[row["fault"]][1] == "drive":  # a finding that names a drive point (or no channel) is on that side
        return effect == "excitation_mass_loading" or kind == "unexplained" and (bool(hits) or not channels)
    if FAULTS[row["fault"]][1] == "housings":
        return bool(set(row["heavy"]) & set(channels))
    lines = set()
    for e in row["truth"]["effects"]:
        lines |= set(e.get("lines") or [])
    where = hits if FAULTS[row["fault"]][1] == "hit" else channels
    return bool(lines & set(where))


def right(row: dict) -> bool:
    """The concealed fault named first, at its place."""
    kind, effect, *_ = row["outcome"]
    return kind == "fault" and effect == NAMED.get(row["fault"], row["fault"]) and placed(row)


def others(rows: list) -> str:
    """What the cases not named right got, with their body and seed: ``unexplained at its place (plate seed 0)``,
    ``×N`` where several cases read alike."""
    counts = Counter(
        f"{r['outcome'][1] if r['outcome'][0] == 'fault' else r['outcome'][0]} "
        f"{'at its place' if placed(r) else 'elsewhere'} ({r['body']} seed {r['seed']})"
        for r in rows
        if not right(r)
    )
    return "; ".join(f"{k}" if v == 1 else f"{k} ×{v}" for k, v in counts.items())


def table(rows: list) -> str:
    """docs/validation.md's table: each concealed fault, its cases, those named right at their place, and the others."""
    out = ["| concealed | n | named right, at its place | the others |", "|---|---|---|---|"]
    for fault in (f for f in FAULTS if any(r["fault"] == f for r in rows)):
        held = [r for r in rows if r["fault"] == fault]
        out.append(f"| {LABELS[fault]} | {len(held)} | {sum(map(right, held))} | {others(held)} |")
    return "\n".join(out)


def summary(rows: list, without: str | None) -> str:
    """The confusion table (concealed × outcome, n per cell) and the rates the diagnosis is judged by: named
    right, located, false alarms."""
    faulty = [r for r in rows if r["fault"] != "none"]
    out = [table(faulty), ""] if faulty and not without else []
    by = {}
    for r in rows:
        kind, effect, *_ = r["outcome"]
        by.setdefault(r["fault"], Counter())[effect if kind == "fault" else kind] += 1
    for fault, counts in by.items():
        out.append(f"{fault:>22} | n={sum(counts.values()):2d} | " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    clean = [r for r in rows if r["fault"] == "none"]
    alarms = sum(r["outcome"][0] == "fault" for r in clean)
    out.append(f"false alarms: {alarms} of {len(clean)} clean files got a fault named")
    if without and without not in FAULTS:  # test physics: the clean files that carry it (a mains file; every file)
        held = [r for r in clean if without != "mains_interference" or r["condition"].startswith("--effect-mains")]
        named = sum(r["outcome"][0] == "fault" for r in held)
        told = sum(r["outcome"][0] == "unexplained" for r in held)
        out.append(f"without {without}: {named} of {len(held)} files carrying it got a fault named, {told} unexplained")
    elif without:
        held = [r for r in faulty if NAMED.get(r["fault"], r["fault"]) == without]
        good = sum(r["outcome"][0] == "unexplained" and placed(r) for r in held)
        out.append(f"without {without}: {good} of {len(held)} files got unexplained at the right place")
    else:
        at = sum(r["outcome"][0] != "none" and placed(r) for r in faulty)
        out.append(f"named right at its place: {sum(map(right, faulty))} of {len(faulty)}; located (named or "
                   f"unexplained): {at}")  # fmt: skip
    worst = np.nanmax([r["worse"] for r in rows] + [-np.inf])
    out.append(f"after worse than identify's before by at most {worst:.2f} of identify's σ (mass, CoG)")
    out.append(f"median {np.median([r['seconds'] for r in rows]):.0f} s per diagnosis")
    return "\n".join(out)


def without(effect: str | None) -> None:
    """Take ``effect`` out of the diagnosis's registry (in each worker too)."""
    if effect:
        registry.EFFECTS = tuple(e for e in registry.EFFECTS if e.name != effect)


def attempted(job: tuple) -> dict | str:
    """One case's row, or the simulator's refusal as text."""
    try:
        return case(*job)
    except RuntimeError as refused:
        return str(refused)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="bracket,structure,plate")
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--faults", default=",".join(FAULTS), help="concealed faults, comma-separated ('': clean only)")
    parser.add_argument("--without", default=None, help="an effect taken out of the diagnosis's registry")
    parser.add_argument("--no-clean", action="store_true", help="faulty cases only")
    parser.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    parser.add_argument("--out", default=None, help="folder for the plans and files (default: a temporary one)")
    args = parser.parse_args()
    without(args.without)
    folder = Path(args.out or tempfile.mkdtemp(prefix="blind-"))
    folder.mkdir(parents=True, exist_ok=True)
    jobs = []
    for body in args.bodies.split(","):
        plan = planned(body, folder)
        planar = body == "plate"
        seeds = range(args.first_seed, args.first_seed + args.seeds)
        cases = [] if args.no_clean else [(None, s, extra) for s in seeds for extra in CLEAN.values()]
        faults = [f for f in args.faults.split(",") if f and not (planar and f in ("sensor_direction",))]
        cases += [(f, s, []) for f in faults for s in seeds]
        jobs += [(plan, fault, seed, extra, folder) for fault, seed, extra in cases]
    rows = []
    with ProcessPoolExecutor(args.jobs, initializer=without, initargs=(args.without,)) as pool:
        for job, row in zip(jobs, pool.map(attempted, jobs)):
            plan, fault, seed, extra, _ = job
            body = plan.parent.name.removeprefix("plan-")
            if isinstance(row, str):  # the simulator's refusal (a cord that no longer holds the body level)
                print(f"{body:>9} {fault or 'none':>22} seed {seed}: not simulated ({row})", flush=True)
                continue
            rows.append(row)
            print(f"{body:>9} {row['fault']:>22} seed {seed} {' '.join(extra) if isinstance(extra, list) else extra:>20}: {row['outcome']} "
                  f"χ² {row['before']} → {row['after']}, after − before {row['worse']:+.2f} σ ({row['seconds']:.0f} s)", flush=True)  # fmt: skip
    print(summary(rows, args.without))


if __name__ == "__main__":
    main()
