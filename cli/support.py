"""The test a plan sets up: the support it chooses and the band it predicts, kept in plan.json.

``massline plan`` and the demo choose them (:func:`plan_test`) on the FE model ``massline simulate`` builds by
default (its element size and ``MODES`` modes), so ``simulate --check`` on the plan's support prints the same
band; the placement report and ``simulate`` read them back (:func:`planned_suspension`).
"""

from __future__ import annotations

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from massline.fe_cache import cached_modes
from massline.meshargs import plan_material
from massline.core.band import Band
from massline.meshes.loader import BodyMesh
from massline.placement.plan_file import band_from_dict, band_to_dict
from massline.virtual.band_prediction import choose_support, support_candidates
from massline.virtual.elastic import ElasticBody, Material
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension
from massline.virtual.tetmesh import default_size

MODES = 20  # elastic modes of the FE model (simulate's default --modes)


def elastic_modes(body: BodyMesh, material: Material, size: float | None, n: int, console: Console):
    """FE model of the body and its n lowest elastic modes, with a progress bar over the stages; kept in the
    cache folder and read back from it by the next command on the same model (:mod:`massline.fe_cache`)."""
    size = default_size(body.mesh) if size is None else float(size)

    def solve():
        with Progress(
            TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(), console=console, transient=True
        ) as bar:
            task = bar.add_task("meshing", total=4)
            stages = iter(range(4))

            def progress(stage: str) -> None:
                bar.update(task, completed=next(stages), description=stage)

            modes = ElasticBody.from_mesh(body.mesh, material, size, body.name, progress).modes(n, progress)
            bar.update(task, completed=4)
        return modes

    modes, kept = cached_modes(body.mesh, material, size, n, solve)
    console.print(
        f"FE model: {modes.n_dofs} DOF, quadratic tetrahedra of {modes.element_size * 1e3:.1f} mm; elastic modes "
        + ", ".join(f"{f:.0f}" for f in modes.frequencies_hz[:5])
        + " … Hz"
        + (" (kept from an earlier run)" if kept else "")
    )
    return modes


def plan_test(body: BodyMesh, mesh_name: str | None, sensors, exciters, console: Console, modes=None):
    """plan.json's ``suspension``, ``band``, ``elastic`` and ``alternatives`` (:mod:`massline.placement.plan_file`),
    and the elastic modes (given, or of simulate's default FE model) they were predicted on."""
    material = plan_material(None, body, mesh_name, console)
    modes = modes or elastic_modes(body, material, None, MODES, console)
    models = [SuspendedBody(body.nominal, modes, s) for s in support_candidates(body.mesh, body.nominal)]
    (chosen, band), *others = choose_support(models, sensors, exciters)
    elastic = {
        "element_size": modes.element_size,
        "modes": len(modes.omega),
        "dofs": modes.n_dofs,
        "youngs": material.youngs,
        "poisson": material.poisson,
        "frequencies_hz": modes.frequencies_hz.tolist(),
    }
    return {
        "suspension": chosen.suspension.as_dict() | {"description": chosen.suspension.describe()},
        "band": band_to_dict(band),
        "elastic": elastic,
        "alternatives": [{"suspension": m.suspension.describe(), "band": band_to_dict(b)} for m, b in others],
    }, modes


def planned_suspension(doc: dict) -> Suspension | None:
    """The support plan.json keeps, or None for a plan written before it kept one."""
    return Suspension.from_dict(doc["suspension"]) if isinstance(doc.get("suspension"), dict) else None


def planned_band(doc: dict) -> Band | None:
    """The band plan.json predicts, or None for a plan written before it kept one."""
    return band_from_dict(doc.get("band"))


def band_phrase(band: Band) -> str:
    """'15.8–51.8 Hz (every FRF within 5 % of its massline's scale)', or why there is none."""
    if not band.exists:
        return f"no band (no FRF run stays within {100 * band.tolerance:g} % of its massline's scale)"
    return f"{band.low:.1f}–{band.high:.1f} Hz (every FRF within {100 * band.tolerance:g} % of its massline's scale)"
