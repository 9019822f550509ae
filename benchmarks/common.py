"""What the benchmark scripts share: timing with peak memory, accelerometers on a surface, `massline plan` and any
command run as a user runs them."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

from massline.core.lines import Lines


def measured(label: str, work, traced: bool = True):
    """Run ``work()``; print its time and, when ``traced``, its peak Python memory (tracemalloc, which slows
    code making many small Python objects); return (result, seconds)."""
    if traced:
        tracemalloc.start()
    start = time.perf_counter()
    result = work()
    seconds = time.perf_counter() - start
    peak = f"   peak {tracemalloc.get_traced_memory()[1] / 2**20:8.1f} MiB" if traced else ""
    if traced:
        tracemalloc.stop()
    print(f"{label:<52} {seconds:8.2f} s{peak}")
    return result, seconds


def surface_lines(mesh, n: int, rng) -> Lines:
    """n area-uniform surface points with their outward normals (uniaxial accelerometers)."""
    faces = rng.choice(len(mesh.faces), n, p=mesh.area_faces / mesh.area)
    points = np.einsum("nk,nkd->nd", rng.dirichlet(np.ones(3), n), mesh.triangles[faces])
    return Lines(points, mesh.face_normals[faces])


def run_plan(arguments: list, out: Path, cache: bool = True) -> tuple[subprocess.CompletedProcess, float]:
    """`massline plan ARGUMENTS --out OUT` in a subprocess (the FE cache off unless ``cache``): the finished
    process and its wall-clock seconds."""
    command = [str(Path(sys.executable).with_name("massline")), "plan", *arguments, "--out", str(out)]
    env = os.environ if cache else {**os.environ, "MASSLINE_CACHE": "off"}
    start = time.perf_counter()
    run = subprocess.run(command, capture_output=True, text=True, env=env, check=False)
    return run, time.perf_counter() - start


def planned(arguments: list, out: Path) -> dict:
    """plan.json of `massline plan ARGUMENTS --out OUT`; a refusal ends the benchmark with its message."""
    run, _ = run_plan(arguments, out)
    if run.returncode != 0:
        raise SystemExit(f"massline plan {' '.join(arguments)} failed: {run.stderr.strip()}")
    return json.loads((out / "plan.json").read_text())


def layout(doc: dict) -> str:
    """A plan file's layout as the tables give it: lines × hits (``9 × 4``)."""
    return f"{len(doc['sensors'])} × {len(doc['exciters'])}"


def massline(*args: str) -> None:
    """Run ``massline ARGS`` as a user does; a refusal raises RuntimeError with its message (the last stderr
    line)."""
    done = subprocess.run([sys.executable, "-m", "massline", *args], capture_output=True, text=True, check=False)
    if done.returncode:
        raise RuntimeError((done.stderr.strip().splitlines() or [f"exit {done.returncode}"])[-1])
