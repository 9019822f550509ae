"""Planning time: `massline plan` end to end on every body it should plan, at default settings.

    python benchmarks/plan_time.py [--options default minimal axes triaxial] [--bodies NAME ...]

Each plan runs in a subprocess through the command line, as a user runs it (`massline plan BODY ... --out DIR`,
the FE model's cache off, so that every run meshes and solves its own), on the bundled bodies, the CAD fixtures
of tests/fixtures/meshes (the two broken on purpose are left out: they are refused) and a cylinder R40 × 120 mm
of 64 sections (trimesh.creation.cylinder, an STL in mm), under four option sets: the default (the cheapest
diagnosable layout), --minimal, --axes and --triaxial 3 --sensors 0 (three triaxial accelerometers). The table
gives the wall seconds of the whole command, the layout (lines × hits), the plain progress lines it printed on
stderr (its stderr is not a terminal), and whether the diagnosable search was stopped by its budget of
evaluations (plan.json); the baseline of each body is its --minimal plan in the same run (× minimal). A plan
refused (a plate with triaxials) is shown as such. The slowest plan is named at the end, against the goal:
every plan under 60 s on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import trimesh

from common import layout, run_plan

from massline.meshes import BUNDLED

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "tests" / "fixtures" / "meshes"
BROKEN = ("busted.STL", "soup.stl")  # refused on purpose
CAD = {f: u for f, u in json.loads((FIXTURES / "units.json").read_text()).items() if f not in BROKEN}  # SOURCES.md
OPTIONS = {
    "default": [],
    "minimal": ["--minimal"],
    "axes": ["--axes"],
    "triaxial": ["--triaxial", "3", "--sensors", "0"],
}
GOAL = 60.0  # seconds a plan may take on 2 cores


def cylinder(folder: Path) -> Path:
    """A turned part as CAD exports it: a cylinder R40 × 120 mm, 64 sections, an STL in mm."""
    path = folder / "cylinder.stl"
    trimesh.creation.cylinder(radius=40.0, height=120.0, sections=64).export(path)
    return path


def bodies(folder: Path) -> dict:
    """Name → the body's arguments to `massline plan`."""
    found = {"cylinder": [str(cylinder(folder)), "--units", "mm", "--density", "2700"]}  # the round part first
    found |= {name: [name] for name in BUNDLED}
    return found | {Path(f).stem: [str(FIXTURES / f), "--units", u, "--density", "2700"] for f, u in CAD.items()}


def timed_plan(body: list, options: list, out: Path) -> dict:
    """One `massline plan` in a subprocess: seconds, exit code, layout, progress lines, stopped by its budget."""
    run, seconds = run_plan([*body, *options], out, cache=False)
    result = {"seconds": seconds, "code": run.returncode, "progress": len(run.stderr.splitlines())}
    if run.returncode != 0:
        return result | {"layout": "refused", "stopped": "", "why": run.stderr.strip().splitlines()[-1][:90]}
    doc = json.loads((out / "plan.json").read_text())
    search = doc["diagnosability"].get("search")
    stopped = "" if search is None else ("yes" if search["stopped"] else "no")
    return result | {"layout": layout(doc), "stopped": stopped}


HEADS = {"minimal": "`--minimal`", "default": "default", "axes": "`--axes`", "triaxial": "`--triaxial 3 --sensors 0`"}


def cell(r: dict) -> str:
    """A plan's layout as docs/validation.md's table gives it: ``9 × 4``, ``refused``, or the layout and "stopped"."""
    return r["layout"] + (" (the diagnosable search stopped at its budget)" if r["stopped"] == "yes" else "")


def table(results: dict, options: list) -> str:
    """docs/validation.md's table: one row per body, each option's layout and seconds."""
    order = [o for o in HEADS if o in options]
    out = ["| body | " + " | ".join(f"{HEADS[o]} | s" for o in order) + " |", "|---" * (1 + 2 * len(order)) + "|"]
    for name, found in results.items():
        out.append(f"| {name} | " + " | ".join(f"{cell(found[o])} | {found[o]['seconds']:.1f}" for o in order) + " |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--options", nargs="+", choices=list(OPTIONS), default=list(OPTIONS))
    parser.add_argument("--bodies", nargs="+", metavar="NAME", help="only these bodies (default: all)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        chosen = {k: v for k, v in bodies(folder).items() if not args.bodies or k in args.bodies}
        print(
            f"{'body':<18} {'options':<9} {'seconds':>8} {'× minimal':>9} {'layout':>8} {'progress':>8} "
            f"{'stopped':>7}",
            flush=True,
        )
        results = {}
        for name, body in chosen.items():
            baseline = None
            for option in sorted(args.options, key=lambda o: o != "minimal"):  # the baseline first
                r = timed_plan(body, OPTIONS[option], folder / f"{name}-{option}")
                results.setdefault(name, {})[option] = r
                baseline = r["seconds"] if option == "minimal" and r["code"] == 0 else baseline
                ratio = f"{r['seconds'] / baseline:9.2f}" if baseline and option != "minimal" else f"{'':>9}"
                print(
                    f"{name:<18} {option:<9} {r['seconds']:8.1f} {ratio} {r['layout']:>8} {r['progress']:>8} "
                    f"{r['stopped'] or '-':>7}" + (f"   ({r['why']})" if r["code"] else ""),
                    flush=True,
                )
    seconds, name, option = max((r["seconds"], n, o) for n, found in results.items() for o, r in found.items())
    verdict = "every plan under" if seconds < GOAL else "over"
    print(f"slowest: {name} {option}, {seconds:.1f} s ({verdict} the {GOAL:.0f} s goal on {os.cpu_count()} cores)\n")
    print(table(results, args.options))


if __name__ == "__main__":
    main()
