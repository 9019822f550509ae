"""Stiff cords and foam, with the mesh: identify's errors before and after the support model, against the bounds.

Each case is what a user runs: ``massline plan BODY`` (the default plan), ``massline simulate`` on a support
(the lab's file: exporter's units, 0 Hz line, coherence, 1 % noise, the FE modes coupled to the support), then
``massline identify FILE`` (before) and ``massline identify FILE --mesh BODY --suspension KIND`` (after: the
support's kind alone, the cord tied where the default ties it; its stiffness and the elastic frequencies are
fitted to the record). Supports:

    cord/4     a cord above the CoG whose bounce is a quarter of the first elastic mode, k = m (2π f₁/4)²
    cord/10    the same at a tenth (the lab matrix's stiff cord)
    foam/10    a foam pad whose bounce is a tenth of the first elastic mode
    foam       the default foam pad (bounce at 4 Hz)

The errors are in units of the bounds (mass 0.3 %, CoG 1 mm, principal moments 1 %): the worst of the three,
before and after; "covered" says whether each property's error is within 2σ of identify's ±, "warned" whether a
warning is printed.

    python benchmarks/stiff_supports.py [--bodies bracket,structure] [--seeds 3] [--supports cord/4,foam]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from common import massline

BOUNDS = {"mass": 0.3, "cog": 1.0, "moments": 1.0}  # %, mm, % (the accuracy identify is held to)
SUPPORTS = {"cord/4": ("cord", 4), "cord/10": ("cord", 10), "foam/10": ("foam", 10), "foam": ("foam", None)}


def support_spec(plan: Path, support: str) -> str:
    """simulate's --suspension for ``support``: its kind, with the stiffness that puts the bounce at f₁/n."""
    kind, fraction = SUPPORTS[support]
    if fraction is None:
        return kind
    doc = json.loads(plan.read_text())
    k = doc["nominal"]["mass"] * (2 * np.pi * doc["elastic"]["frequencies_hz"][0] / fraction) ** 2
    return f"{kind}:k={k:.6g}"


def errors(found: dict, true: dict) -> dict:
    """Each property's error in units of its bound, and in units of identify's 1-σ."""
    std = found["std"]
    mass = abs(found["mass"] / true["mass"] - 1) * 100
    cog = np.abs(np.subtract(found["cog"], true["cog"])) * 1e3
    moments = np.abs(np.divide(found["principal_moments"], true["principal_moments"]) - 1) * 100
    z = [
        abs(found["mass"] - true["mass"]) / std["mass"],
        *(np.abs(np.subtract(found["cog"], true["cog"])) / np.asarray(std["cog"])),
        *(np.abs(np.subtract(found["principal_moments"], true["principal_moments"]))
          / np.asarray(std["principal_moments"])),
    ]
    bounds = max(mass / BOUNDS["mass"], cog.max() / BOUNDS["cog"], moments.max() / BOUNDS["moments"])
    return {"bounds": bounds, "z": max(z), "warned": bool(found["warnings"])}


def case(body: str, support: str, seed: int, folder: Path) -> dict:
    plan = folder / f"plan-{body}" / "plan.json"
    if not plan.exists():
        massline("plan", body, "--out", str(plan.parent), "--force")
    path = folder / f"{body}-{support.replace('/', '_')}-{seed}.uff"
    massline("simulate", str(plan), "--seed", str(seed), "--suspension", support_spec(plan, support), "--out",
             str(path), "--force")  # fmt: skip
    true = json.loads(path.with_suffix(".truth.json").read_text())["loaded"]
    row = {}
    for label, extra in (("before", []), ("after", ["--mesh", body, "--suspension", SUPPORTS[support][0]])):
        out = path.with_suffix(f".{label}.json")
        try:
            massline("identify", str(path), "--json", str(out), "--force", *extra)
            row[label] = errors(json.loads(out.read_text()), true)
        except RuntimeError as refused:
            row[label] = {"refused": str(refused)}
    return row


def text(result: dict) -> str:
    if "refused" in result:
        return "refused"
    covered = "covered" if result["z"] <= 2 else f"{result['z']:.1f}σ"
    return f"{result['bounds']:.2f}× ({covered}{', warned' if result['warned'] else ''})"


def times(x: float) -> str:
    """An error over its bound to two or three digits: 0.13, 4.3, 33, 922,534."""
    return f"{x:.2f}" if x < 1 else f"{x:.1f}" if x < 10 else f"{x:,.0f}"


def spread(results: list) -> str:
    """The seeds' errors over the bound as a range, and the refusals: ``0.13–0.63×``, ``156–922,534×, 1 refused``."""
    values = sorted(r["bounds"] for r in results if "refused" not in r)
    refused = len(results) - len(values)
    low, high = (times(values[0]), times(values[-1])) if values else ("", "")
    shown = [] if not values else [low + ("" if low == high else "–" + high) + "×"]
    return ", ".join(shown + ([f"{refused} refused"] if refused else []))


LABELS = {"cord/4": "cord, f₁/4", "cord/10": "cord, f₁/10", "foam/10": "foam, f₁/10", "foam": "foam, 4 Hz"}


def table(rows: dict) -> str:
    """docs/validation.md's table: each body and support, the worst error over its bound before and after, over the
    seeds."""
    out = ["| body | support | before | after |", "|---|---|---|---|"]
    for (body, support), results in rows.items():
        before, after = ([r[label] for r in results] for label in ("before", "after"))
        out.append(f"| {body} | {LABELS[support]} | {spread(before)} | {spread(after)} |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="bracket,structure")
    parser.add_argument("--supports", default=",".join(SUPPORTS))
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="stiff-"))
    print("| body | support | seed | before: worst error / bound | after (--mesh --suspension) |")
    print("|---|---|---|---|---|")
    inside = total = 0
    rows = {}
    for body in args.bodies.split(","):
        for support in args.supports.split(","):
            for seed in range(args.seeds):
                row = case(body, support, seed, folder)
                rows.setdefault((body, support), []).append(row)
                after = row["after"]
                total += 1
                inside += "refused" not in after and (after["bounds"] <= 1 or after["z"] <= 2 and after["warned"])
                print(f"| {body} | {support} | {seed} | {text(row['before'])} | {text(after)} |", flush=True)
    print(f"\nafter: {inside} of {total} inside the bounds, or covered by 2σ and warned\n")
    print(table(rows))


if __name__ == "__main__":
    main()
