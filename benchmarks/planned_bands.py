"""The support each bundled body's default plan chooses and the band it predicts: the figures the docs give.

    python benchmarks/planned_bands.py [--bodies NAME ...]

Each plan runs through the command line as a user runs it (`massline plan BODY --out DIR`; the structure also
with the demo's budget, `--sensors 14 --exciters 4`), so the band is the one the plan file, the placement report,
`simulate --check` and the demo print: predicted on the FE model `simulate` builds by default, the widest band
over the supports weighed at the tightest tolerance (1, 2 or 5 %) that holds one an octave wide. Beside it, what
the default plan's search for the cheapest diagnosable layout spent (plan.json's ``search``; "—" where a budget
was given and nothing was searched). Everything printed is deterministic (the FE model is solved again where the
cache holds no modes for the body).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from common import layout, planned

from massline.meshes import BUNDLED

PLANS = {"structure": [[], ["--sensors", "14", "--exciters", "4"]], "bracket": [[]], "plate": [[]]}


def band_of(name: str, options: list, out: Path) -> str:
    """One table row: the plan's layout, its support and its band, from plan.json."""
    doc = planned([name, *options], out)
    band = doc["band"]
    given = " ".join(options) or "(default)"
    search = doc["diagnosability"].get("search") or {}
    spent = f"{search['spent']:,}" if "spent" in search else "—"
    return (f"| {name} | {given} | {layout(doc)} | {spent} | {doc['suspension']['description']} | "
            f"{band['low_hz']:.1f}–{band['high_hz']:.1f} | {band['tolerance']:.0%} |").replace("%", " %")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", choices=list(BUNDLED), default=list(PLANS))
    args = parser.parse_args()
    print("| body | plan options | layout | diagnosable search, evaluations | support chosen | planned band, Hz | "
          "tolerance |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.bodies:
            for k, options in enumerate(PLANS.get(name, [[]])):
                print(band_of(name, options, Path(scratch) / f"{name}-{k}"), flush=True)


if __name__ == "__main__":
    main()
