"""Criterion E against D on the bundled bodies' minimal layouts: the criterion-E sentence in docs/validation.md.

Each plan runs through the command line (`massline plan BODY --minimal [--criterion E]`); the figures come from
plan.json: the smallest eigenvalue λ_min of the scaled information F, E's gain in it over D's layout, E's
certified efficiency (λ_min / λ_min,best ≥ the bound) and what E gives up in log det F.

    python benchmarks/criteria.py [--bodies structure bracket plate]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from common import planned

from massline.meshes import BUNDLED


def criterion_of(name: str, criterion: str, out: Path) -> dict:
    """plan.json's criterion section of `massline plan NAME --minimal --criterion CRITERION`."""
    return planned([name, "--minimal", "--criterion", criterion], out)["criterion"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", default=sorted(BUNDLED))
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="criteria-"))
    print(f"{'body':<10} {'λ_min D':>10} {'λ_min E':>10} {'E / D':>7} {'E-efficiency ≥':>15} {'log det D':>10} "
          f"{'log det E':>10}")  # fmt: skip
    for name in args.bodies:
        d = criterion_of(name, "D", folder / f"{name}-D")
        e = criterion_of(name, "E", folder / f"{name}-E")
        gain = e["smallest_eigenvalue"] / d["smallest_eigenvalue"]
        print(f"{name:<10} {d['smallest_eigenvalue']:10.4g} {e['smallest_eigenvalue']:10.4g} {gain:6.2f}× "
              f"{100 * e['efficiency_lower_bound']:14.0f} % {d['log_det']:10.1f} {e['log_det']:10.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
