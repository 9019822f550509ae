"""One BLAS thread against OpenBLAS's pool of one per core: a small least squares and the whole demo.

massline's entry point sets ``OPENBLAS_NUM_THREADS`` (and OMP's, MKL's) to 1 unless the environment says
otherwise (``massline/__main__.py``), and the tests run likewise (``tests/conftest.py``). This prints, for each
setting, the time of a 1200 × 4 least squares with 60 right-hand sides (a band fit's tail coefficients, the
size identify solves thousands of times) and of ``massline demo`` (plan, virtual test, identify, diagnose),
each the best of ``--repeats`` runs in a fresh process, and their ratio. With ``--busy`` a second process keeps
one core busy meanwhile, as a second test worker or other work does.

    python benchmarks/blas_threads.py [--repeats 2] [--busy]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

KERNEL = """
import time, numpy as np
rng = np.random.default_rng(0)
X, Y = rng.normal(size=(1200, 4)), rng.normal(size=(1200, 60))
start = time.perf_counter()
for _ in range(200):
    np.linalg.lstsq(X, Y, rcond=None)
print((time.perf_counter() - start) / 200)
"""


def environment(threads: int) -> dict:
    return {**os.environ, "OPENBLAS_NUM_THREADS": str(threads), "OMP_NUM_THREADS": str(threads),
            "MKL_NUM_THREADS": str(threads), "MASSLINE_CACHE": "off"}  # fmt: skip


def kernel_seconds(threads: int) -> float:
    done = subprocess.run([sys.executable, "-c", KERNEL], env=environment(threads), capture_output=True, text=True)
    return float(done.stdout)


def demo_seconds(threads: int) -> float:
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        command = [sys.executable, "-m", "massline", "demo", "--out", os.path.join(folder, "demo")]
        subprocess.run(command, env=environment(threads), capture_output=True, check=True)
        return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--busy", action="store_true", help="keep one core busy with another process meanwhile")
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if args.busy else None
    try:
        rows = {}
        for threads in (cores, 1):
            kernel = min(kernel_seconds(threads) for _ in range(args.repeats))
            demo = min(demo_seconds(threads) for _ in range(args.repeats))
            rows[threads] = (kernel, demo)
            print(f"{threads} BLAS thread(s){' (one core busy)' if busy else ''}: least squares {kernel * 1e3:.2f} ms, "
                  f"massline demo {demo:.1f} s", flush=True)
    finally:
        if busy:
            busy.kill()
    (k_pool, d_pool), (k_one, d_one) = rows[cores], rows[1]
    print(f"one thread against {cores}: least squares {k_pool / k_one:.1f}× faster, demo {d_pool / d_one:.2f}× faster")


if __name__ == "__main__":
    main()
