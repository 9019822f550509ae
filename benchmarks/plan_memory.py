"""Peak memory of `massline plan` against the number of candidate sample points: the figures behind `plan`'s
memory check (massline/cli/plan.py: BASE_BYTES + BYTES_PER_CANDIDATE × points, × AXES_FACTOR with --axes).

    python benchmarks/plan_memory.py [--candidates 100000 300000] [--axes]

Each plan runs in its own process through the command line (`massline plan structure --minimal --candidates N`,
the FE cache as it is), and its peak resident memory is the kernel's (``wait4``'s ru_maxrss), the whole process
with its libraries. Printed beside it: what the check estimates for that count, and the fit of a line through the
peaks (bytes per point and the base).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from massline.cli.plan import AXES_FACTOR, BASE_BYTES, BYTES_PER_CANDIDATE


def peak(arguments: list, out: Path) -> float:
    """Peak resident bytes of `massline plan ARGUMENTS --out OUT` (its own process, Linux's ru_maxrss in kB)."""
    command = [str(Path(sys.executable).with_name("massline")), "plan", *arguments, "--out", str(out)]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    if status != 0:
        raise SystemExit(f"{' '.join(command)} failed: {process.stderr.read().decode().strip()}")
    return usage.ru_maxrss * 1024.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--candidates", nargs="+", type=int, default=[100_000, 300_000])
    parser.add_argument("--axes", action="store_true", help="plan with --axes (three lines per point)")
    args = parser.parse_args()
    extra = ["--axes"] if args.axes else []
    factor = AXES_FACTOR if args.axes else 1.0
    print(f"| sample points | peak GB{' (--axes)' if args.axes else ''} | the check's estimate, GB |")
    print("|---|---|---|")
    peaks = []
    with tempfile.TemporaryDirectory() as scratch:
        for k, n in enumerate(args.candidates):
            bytes_ = peak(["structure", "--minimal", "--candidates", str(n), *extra], Path(scratch) / str(k))
            peaks.append(bytes_)
            estimate = BASE_BYTES + BYTES_PER_CANDIDATE * factor * n
            print(f"| {n:,} | {bytes_ / 1e9:.2f} | {estimate / 1e9:.2f} |", flush=True)
    if len(peaks) > 1:
        slope, base = np.polyfit(args.candidates, peaks, 1)
        print(f"a line through the peaks: {base / 1e6:.0f} MB + {slope / 1e3:.2f} kB per point "
              f"(the check: {BASE_BYTES / 1e6:.0f} MB + {BYTES_PER_CANDIDATE * factor / 1e3:.2f} kB)")


if __name__ == "__main__":
    main()
