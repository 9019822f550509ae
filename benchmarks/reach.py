"""What the reach check takes and costs: the candidate places it drops, by reason, and its seconds, per body.

    python benchmarks/reach.py [--bodies NAME ...]

For each bundled body and the flanged hub of tests/fixtures/meshes/flanged_hub.stl (mm, 2700 kg/m³): the candidate
points (400 asked, seed 0) that take a hit and an accelerometer, the places each reason dropped (placement/reach.py
for the hammer's approach, the housing and the cable), the seconds of the whole candidate enumeration, and the ray
casts' time per point (the three checks of :func:`massline.placement.reach.reach`).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from massline.meshes import BUNDLED
from massline.meshes.loader import load_body
from massline.placement.candidates import CandidateOptions, candidate_points
from massline.placement.mountable import Surface
from massline.placement.reach import reach

HUB = Path(__file__).resolve().parents[1] / "tests" / "fixtures" / "meshes" / "flanged_hub.stl"


def body(name: str):
    return load_body(HUB, "mm", 2700) if name == "hub" else load_body(BUNDLED[name].path, "m", BUNDLED[name].density)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", default=[*BUNDLED, "hub"])
    args = parser.parse_args()
    for name in args.bodies:
        b = body(name)
        surface = Surface.of(b.mesh)
        start = time.perf_counter()
        points = candidate_points(b.mesh, CandidateOptions(), surface)
        enumerated = time.perf_counter() - start
        start = time.perf_counter()
        reach(b.mesh, points.points, points.normals, CandidateOptions().reach_sizes)
        per_point = (time.perf_counter() - start) / max(len(points), 1)
        dropped = ", ".join(f"{n} {reason.split(' (')[0]}" for reason, n in points.excluded.items() if n)
        print(
            f"{name}: {len(points)} candidate points ({len(points.hit_points())} hits, {len(points.sensor_points())} "
            f"accelerometers); dropped: {dropped}; enumeration {enumerated:.2f} s, "
            f"reach {1e3 * per_point:.2f} ms a point"
        )


if __name__ == "__main__":
    main()
