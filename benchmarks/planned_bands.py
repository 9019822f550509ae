"""The support each bundled body's default plan chooses and the band it predicts: the figures the docs give.

    python benchmarks/planned_bands.py [--bodies NAME ...] [--coretypes KERNEL ...]

Each plan runs through the command line as a user runs it (`massline plan BODY --out DIR`; the structure also
with the demo's budget, `--sensors 14 --exciters 4`), so the band is the one the plan file, the placement report,
`simulate --check` and the demo print: predicted on the FE model `simulate` builds by default, the widest band
over the supports weighed at the tightest tolerance (1, 2 or 5 %) that holds one an octave wide. The table is
deterministic on a BLAS kernel (the FE model is solved again where the cache holds no modes for the body).

Below it, what each default plan's search for the cheapest diagnosable layout spent (plan.json's ``search``; the
plans given a budget search nothing). That count is not the same on every machine: the walk towards a
diagnosable layout meets trials whose excess leverage is equal in exact arithmetic (two channels' confusions
at 1, say) and takes the one rounding puts first, so the BLAS kernel's order of operations steers which
exchanges it tries, and how many (on its way to the same layout, on every kernel measured but Sandybridge's for
the bracket). ``--coretypes`` plans the searched bodies again with each OpenBLAS kernel named
(``OPENBLAS_CORETYPE``: Haswell, Zen, Sandybridge, SkylakeX, …, the kernels of other CPUs, run on this one) and
prints their counts, and the rows of the table that kernel plans otherwise.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

from common import layout, planned

from massline.meshes import BUNDLED
from massline.placement.diagnosable_plan import EVALUATIONS

PLANS = {"structure": [[], ["--sensors", "14", "--exciters", "4"]], "bracket": [[]], "plate": [[]]}


def band_of(name: str, options: list, out: Path) -> tuple[str, int | None]:
    """One table row (the plan's layout, its support and its band, from plan.json) and what the diagnosable
    search spent (None where the budget was given)."""
    doc = planned([name, *options], out)
    band = doc["band"]
    given = " ".join(options) or "(default)"
    search = doc["diagnosability"].get("search") or {}
    row = (f"| {name} | {given} | {layout(doc)} | {doc['suspension']['description']} | "
           f"{band['low_hz']:.1f}–{band['high_hz']:.1f} | {band['tolerance']:.0%} |").replace("%", " %")  # fmt: skip
    return row, search.get("spent")


def spent_line(spent: dict, kernel: str | None = None) -> str:
    """``diagnosable search, evaluations of 300,000: structure 62,600, …`` (the kernel named when one was set)."""
    where = f" (OPENBLAS_CORETYPE={kernel})" if kernel else ""
    counts = ", ".join(f"{name} {count:,}" for name, count in spent.items())
    return f"diagnosable search, evaluations of {EVALUATIONS:,}{where}: {counts}"


@contextmanager
def coretype(kernel: str):
    """The plans run meanwhile with OpenBLAS's ``kernel`` (its environment variable, which the command inherits)."""
    before = os.environ.get("OPENBLAS_CORETYPE")
    os.environ["OPENBLAS_CORETYPE"] = kernel
    try:
        yield
    finally:
        if before is None:
            del os.environ["OPENBLAS_CORETYPE"]
        else:
            os.environ["OPENBLAS_CORETYPE"] = before


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", choices=list(BUNDLED), default=list(PLANS))
    parser.add_argument("--coretypes", nargs="+", default=[], metavar="KERNEL",
                        help="OpenBLAS kernels to plan the searched bodies again with")  # fmt: skip
    args = parser.parse_args()
    print("| body | plan options | layout | support chosen | planned band, Hz | tolerance |")
    print("|---|---|---|---|---|---|")
    rows, spent = {}, {}
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.bodies:
            for k, options in enumerate(PLANS.get(name, [[]])):
                row, count = band_of(name, options, Path(scratch) / f"{name}-{k}")
                print(row, flush=True)
                if count is not None:
                    rows[name], spent[name] = row, count
        print(spent_line(spent), flush=True)
        for kernel in args.coretypes:
            with coretype(kernel):
                found = {name: band_of(name, [], Path(scratch) / f"{name}-{kernel}") for name in spent}
            print(spent_line({name: count for name, (_, count) in found.items()}, kernel), flush=True)
            for name, (row, _) in found.items():
                if row != rows[name]:
                    print(f"  planned otherwise with {kernel}: {row}", flush=True)


if __name__ == "__main__":
    main()
