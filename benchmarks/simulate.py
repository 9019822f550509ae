"""Virtual-test cost on a ~50k-DOF body: FE assembly, modes, 100 FRFs × 2,000 lines.

Prints time and peak memory (tracemalloc: Python-side allocations, including
numpy/scipy arrays) of each stage, and compares the FRFs of the reduced
modal model with the baseline a plain FE code would use: a sparse direct
solve of (K + iD − ω²M) u = f at every spectral line (timed on a few lines and
scaled to 2,000, stated as such).

    python benchmarks/simulate.py [--dofs 50000]
"""

from __future__ import annotations

import argparse

import numpy as np
import scipy.sparse.linalg
from common import measured, surface_lines

from massline.meshes import BUNDLED
from massline.placement.hand_layouts import structure_exciters
from massline.meshes.loader import load_body
from massline.virtual.attachment import point_above
from massline.virtual.band_prediction import recommend_suspension
from massline.virtual.elastic import ElasticBody, Material
from massline.virtual.suspended import SuspendedBody
from massline.virtual.tetmesh import size_for_dofs, tetrahedralise


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dofs", type=int, default=50_000)
    parser.add_argument("--modes", type=int, default=30)
    args = parser.parse_args()
    body = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density)
    material = Material(BUNDLED["structure"].youngs, BUNDLED["structure"].poisson, body.density)
    size = size_for_dofs(body.mesh, args.dofs)
    print(f"structure ({body.nominal.mass:.3f} kg), element size {size * 1e3:.2f} mm, {args.modes} modes")

    (points, tets), _ = measured("tetrahedral meshing (netgen)", lambda: tetrahedralise(body.mesh, size))
    fe = ElasticBody(points, tets, material, size)
    measured("assembly of K and M (P2)", lambda: (fe.stiffness, fe.mass))
    print(f"{'':<38} {fe.n_dofs} DOF, {len(tets)} tetrahedra")
    modes, _ = measured(f"{args.modes} elastic modes (shift-invert)", lambda: fe.modes(args.modes))
    print(f"{'':<38} {modes.frequencies_hz[0]:.1f} … {modes.frequencies_hz[-1]:.1f} Hz")

    rng = np.random.default_rng(0)
    sensors = surface_lines(body.mesh, 34, rng)
    exciters = structure_exciters()
    model = SuspendedBody(body.nominal, modes)
    model = SuspendedBody(body.nominal, modes, recommend_suspension(model, point_above(body.mesh, body.nominal.cog)[0]))
    frequencies = np.linspace(0.5, 1.5 * modes.frequencies_hz[0], 2000)
    H, reduced = measured(
        f"{len(sensors)}×{len(exciters)} = {len(sensors) * len(exciters)} FRFs × 2000 lines",
        lambda: model.accelerance(
            frequencies, sensors.points, sensors.directions, exciters.points, exciters.directions
        ),
    )

    K, M = fe.stiffness.tocsc(), fe.mass.tocsc()
    sample = frequencies[::400]

    def direct():
        for f in sample:
            w = 2 * np.pi * f
            scipy.sparse.linalg.splu((K * (1 + 0.002j) - w**2 * M).tocsc())

    _, seconds = measured(f"baseline: sparse LU at {len(sample)} lines", direct)
    full = seconds / len(sample) * 2000
    print(f"baseline scaled to 2000 lines: {full:.0f} s; reduced modal model is {full / reduced:.0f}× faster")
    print(f"FRF array {H.nbytes / 2**20:.1f} MiB")


if __name__ == "__main__":
    main()
