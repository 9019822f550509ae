"""A channel read through its chain: ``channel_delay`` and ``mount_resonance`` named, sized and undone, blind.

Each case is what a user runs: ``massline plan BODY`` (the default plan), ``massline simulate`` (1 % noise, the
default cord, the FE modes) with the effect on one or two channels drawn from the seed, then ``diagnose`` with
the mesh's body on the plan's band (``--band``, as docs/diagnosing.md asks; ``--band identify``: identify's own,
wider, where the body's elastic tails reach further in). Sizes: a delay of 60–200 µs; a mount resonating at
2–4 × the plan's band top. A case is a hit
when every concealed channel is named with the effect, its size within 3σ of the truth, and the body after is
within identify's bounds (mass 0.3 %, CoG 1 mm, principal moments 1 %; a plate's in-plane moments). The clean
files count the false alarms (a row effect, or a misfit in frequency, named on a file with none); ``--without``
takes each effect out of the registry and counts the files that get ``unexplained`` at every concealed channel
with the effect's signature (phase_linear, rising).

    python benchmarks/row_effects.py [--bodies plate,bracket,structure] [--seeds 6] [--first-seed 0]
        [--parts named,without,clean] [--band plan|identify] [--out DIR]

Prints one line per case and the hit rates with their n.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from common import massline

import massline.identify.diagnose.effects as registry
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.meshes import BUNDLED
from massline.meshes.loader import load_body

EFFECTS = {"channel_delay": "phase_linear", "mount_resonance": "rising"}  # each effect's signature
BOUNDS = (0.003, 1e-3, 0.01)  # mass (fraction), CoG (m), principal moments (fraction)


def planned(body: str, folder: Path) -> Path:
    """The body's default plan (planned once per folder)."""
    plan = folder / f"plan-{body}" / "plan.json"
    if not plan.exists():
        massline("plan", body, "--out", str(plan.parent), "--force")
    return plan


def drawn(plan: Path, effect: str, seed: int) -> tuple[list, list]:
    """The channels (0-based, one or two, at different points) and sizes of a case, from ``seed``."""
    doc = json.loads(plan.read_text())
    rng = np.random.default_rng(seed)
    points = np.array([s["point"] for s in doc["sensors"]])
    first = int(rng.integers(len(points)))
    others = [i for i in range(len(points)) if np.linalg.norm(points[i] - points[first]) > 1e-3]
    channels = [first] + ([int(rng.choice(others))] if rng.random() < 0.5 else [])
    top = doc["band"]["high_hz"]
    sizes = [float(rng.uniform(60e-6, 200e-6) if effect == "channel_delay" else rng.uniform(2, 4) * top)
             for _ in channels]  # fmt: skip
    return channels, sizes


def within_bounds(body, bare, planar: bool) -> bool:
    """The body within identify's bounds of the bare one (a plate: mass, in-plane CoG, J_xx and J_yy)."""
    if planar:
        moments = [body.inertia_cog[k, k] / bare.inertia_cog[k, k] - 1 for k in (0, 1)]
        cog = body.cog[:2] - bare.cog[:2]
    else:
        moments = body.principal_moments / bare.principal_moments - 1
        cog = body.cog - bare.cog
    errors = (abs(body.mass / bare.mass - 1), np.abs(cog).max(), np.abs(moments).max())
    return all(e < bound for e, bound in zip(errors, BOUNDS))


def case(plan: Path, effect: str | None, seed: int, folder: Path, held: bool = True, band: str = "plan") -> dict:
    """Simulate one case, diagnose it (the effect out of the registry unless ``held``) on the plan's band or
    identify's (``band``); its outcome."""
    channels, sizes = drawn(plan, effect, seed) if effect else ([], [])
    path = folder / f"{plan.parent.name}-{effect or 'clean'}-{seed}.uff"
    args = [a for c, s in zip(channels, sizes) for a in ("--effect", f"{effect}={s:.6g}@{c + 1}")]
    massline("simulate", str(plan), "--seed", str(seed), "--out", str(path), "--force", *args)
    body = plan.parent.name.removeprefix("plan-")
    mesh = load_body(BUNDLED[body].path, "m", BUNDLED[body].density)
    full = registry.EFFECTS
    registry.EFFECTS = full if held else tuple(e for e in full if e.name != effect)
    try:
        planned_band = json.loads(plan.read_text())["band"]
        given = (planned_band["low_hz"], planned_band["high_hz"]) if band == "plan" else None
        found = diagnose_recording(path, given, mesh.nominal)
    finally:
        registry.EFFECTS = full
    named = [f for f in found.findings if f.effect in EFFECTS]
    frequency = [f for f in found.findings if f.parameters.get("shape") == "in_frequency"]
    sized, signed = [], []
    for c, s in zip(channels, sizes):
        here = [f for f in named if f.effect == effect and c in f.channels]
        key = f"{'delay_s' if effect == 'channel_delay' else 'mount_hz'}"
        sized.append(bool(here) and abs(here[0].parameters[key] - s) <= 3 * here[0].parameters[f"{key}_std"])
        shapes = [f for f in frequency if c in f.channels]
        signed.append(bool(shapes) and shapes[0].parameters["signature"]["signature"] == EFFECTS.get(effect))
    body_ok = found.after_body is not None and within_bounds(found.after_body, mesh.nominal, found.planar)
    return {
        "body": body, "effect": effect or "none", "seed": seed, "held": held, "channels": [c + 1 for c in channels],
        "sizes": sizes, "found": [(f.effect, [c + 1 for c in f.channels], sizes_of(f)) for f in named + frequency],
        "hit": bool(all(sized) and body_ok if held else all(signed)), "within": bool(body_ok),
        "false_alarm": bool(named or frequency) and not effect,
    }  # fmt: skip


def sizes_of(finding) -> list:
    """A finding's size and 1-σ (a delay's s, a mount's Hz; none for an unexplained row)."""
    p = finding.parameters
    return [p.get(k, p.get(k.replace("delay_s", "mount_hz"))) for k in ("delay_s", "delay_s_std")]


def rate(rows: list, key: str) -> str:
    n = len(rows)
    k = sum(r[key] for r in rows)
    return f"{k}/{n} ({100 * k / max(n, 1):.0f} %)"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="plate,bracket,structure")
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--parts", default="named,without,clean", help="the effects named, out of the registry, clean")
    parser.add_argument("--band", choices=("plan", "identify"), default="plan")
    parser.add_argument("--out", help="keep the plans and files here (default a temporary folder)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(args.out or tmp)
        folder.mkdir(parents=True, exist_ok=True)
        rows = []
        for body in args.bodies.split(","):
            plan = planned(body, folder)
            seeds, parts = range(args.first_seed, args.first_seed + args.seeds), args.parts.split(",")
            runs = [(e, s, True) for e in EFFECTS for s in seeds] if "named" in parts else []
            runs += [(e, s, False) for e in EFFECTS for s in seeds] if "without" in parts else []
            runs += [(None, s, True) for s in seeds] if "clean" in parts else []
            for effect, seed, held in runs:
                row = case(plan, effect, seed, folder, held, args.band)
                rows.append(row)
                print(json.dumps(row), flush=True)
    for effect in EFFECTS:
        named = [r for r in rows if r["effect"] == effect and r["held"]]
        left = [r for r in rows if r["effect"] == effect and not r["held"]]
        print(f"{effect}: named at every channel, size within 3σ, body within bounds: {rate(named, 'hit')}; "
              f"out of the registry, unexplained at every channel with its signature: {rate(left, 'hit')}")
    clean = [r for r in rows if r["effect"] == "none"]
    print(f"clean files with a row effect or a misfit in frequency named: {rate(clean, 'false_alarm')} "
          f"(diagnosed on {'the plan' if args.band == 'plan' else 'identify'}'s band)")


if __name__ == "__main__":
    main()
