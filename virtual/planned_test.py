"""The test a plan sets up: the support it chooses and the band it predicts, kept in plan.json.

``massline plan`` and the demo choose them (:func:`plan_test`) on the FE model ``massline simulate`` builds by
default (its element size and ``MODES`` modes), so ``simulate --check`` on the plan's support prints the same
band; the placement report and ``simulate`` read them back (:func:`planned_suspension`, :func:`planned_band`).
The FE modes are kept on disk between runs (:mod:`massline.virtual.fe_cache`).

``progress(stage, done, total)``, where a function takes it, is called as each stage of the FE solve starts
(``done`` of ``total`` stages finished) and once at the end (``done == total``); it is not called when the
modes are read back from the cache. None: silent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core.band import Band, band_from_dict, band_to_dict
from massline.core.errors import MasslineError
from massline.core.numbers import vector_text
from massline.meshes import BUNDLED
from massline.meshes.loader import UNITS, BodyMesh, load_body
from massline.virtual.band_prediction import choose_support, support_candidates, support_rig
from massline.virtual.elastic import ElasticBody, ElasticModes, Material
from massline.virtual.fe_cache import cached_modes
from massline.virtual.rigging import mm
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension

MODES = 20  # elastic modes of the FE model (simulate's default --modes)
MESH_MATCH = 1e-6  # relative mass and CoG (of the body's size) within which a mesh is the plan's body
MOST_PADS_SAID = 6  # contact points of a foam pad the rig's description lists
FE_STAGES = 4  # meshing, assembling stiffness, assembling mass, solving for modes


@dataclass(frozen=True)
class FEModel:
    """The elastic modes of a body's FE model and how they were found.

    Attributes
    ----------
    modes : ElasticModes
        The free body's lowest elastic modes (frequencies in Hz through ``modes.frequencies_hz``).
    material : Material
        Young's modulus (Pa), Poisson's ratio and density (kg/m³) they were solved with.
    kept : bool
        Read back from the cache (:mod:`massline.virtual.fe_cache`) instead of solved.
    assumed : str or None
        The metal assumed when no material was given and the body is not a bundled one (its name), else None.
    """

    modes: ElasticModes
    material: Material
    kept: bool = False
    assumed: str | None = None


def body_material(body: BodyMesh, mesh_name: str | None = None, material: str | None = None) -> Material:
    """Young's modulus (Pa) and Poisson's ratio of ``body``: ``material`` (a name or 'E,NU'), else the bundled
    body's, else the closest-density metal's (:func:`assumed_material`); the density (kg/m³) is the body's."""
    if material is None and mesh_name in BUNDLED:
        return Material(BUNDLED[mesh_name].youngs, BUNDLED[mesh_name].poisson, body.density)
    return Material.parse(material or Material.closest(body.density), body.density)


def assumed_material(body: BodyMesh, mesh_name: str | None = None, material: str | None = None) -> str | None:
    """The metal :func:`body_material` assumes for ``body`` (given no material and not bundled), or None."""
    if material is not None or mesh_name in BUNDLED:
        return None
    return Material.closest(body.density)


def fe_model(
    body: BodyMesh,
    material: Material,
    *,
    size: float | None = None,
    n: int = MODES,
    progress=None,
    assumed: str | None = None,
) -> FEModel:
    """The FE model of ``body`` (quadratic tetrahedra of ``size`` m, default :func:`.default_tetrahedra`) and its ``n``
    lowest elastic modes, read from the cache when an earlier run solved the same model, else solved (reporting
    each stage to ``progress(stage, done, total)``) and kept there."""

    def solve() -> ElasticModes:
        stages = iter(range(FE_STAGES))

        def stage(name: str) -> None:
            if progress is not None:
                progress(name, next(stages), FE_STAGES)

        modes = ElasticBody.from_mesh(body.mesh, material, size, body.name, stage).modes(n, stage)
        if progress is not None:
            progress("solving for modes", FE_STAGES, FE_STAGES)
        return modes

    modes, kept = cached_modes(body.mesh, material, size, n, solve)
    return FEModel(modes, material, kept, assumed)


def plan_fe_model(body: BodyMesh, mesh_name: str | None, progress=None) -> FEModel:
    """simulate's default FE model of ``body`` (``MODES`` modes), in its material (:func:`body_material`; the
    metal assumed named), from the cache or solved (``progress`` over the solve)."""
    material = body_material(body, mesh_name)
    return fe_model(body, material, progress=progress, assumed=assumed_material(body, mesh_name))


def plan_test(
    body: BodyMesh, mesh_name: str | None, sensors, exciters, progress=None, fe: FEModel | None = None, housings=None
) -> tuple[dict, FEModel]:
    """Choose the support a test of ``sensors`` × ``exciters`` hangs ``body`` on, and predict its band.

    Parameters
    ----------
    body : BodyMesh
        The body (m, kg, frame O xyz).
    mesh_name : str or None
        The mesh as plan.json names it (a bundled body's name gives its material).
    sensors, exciters : Lines
        The plan's accelerometer and hit lines (m).
    progress : callable, optional
        ``progress(stage, done, total)`` over the FE solve (module docstring).
    fe : FEModel, optional
        The free body's elastic modes to predict on; default: :func:`plan_fe_model` (solved or read back here).
    housings : (masses (k,) kg, points (k, 3) m), optional
        The accelerometers' housings the test carries (:func:`massline.virtual.acquisition.accelerometer_masses`).

    Returns
    -------
    test : dict
        plan.json's ``suspension``, ``rig`` (:func:`rig_entry`), ``band``, ``elastic`` and ``alternatives``
        (:mod:`massline.placement.plan_file`).
    fe : FEModel
        The elastic modes they were predicted on and their material.
    """
    fe = plan_fe_model(body, mesh_name, progress) if fe is None else fe
    modes, material = fe.modes, fe.material
    housings = (np.zeros(0), np.zeros((0, 3))) if housings is None else housings
    carried = SuspendedBody(body.nominal, None, Suspension(), *housings).loaded  # what the support holds level
    models = [SuspendedBody(body.nominal, modes, s, *housings) for s in support_candidates(body.mesh, carried)]
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
        "rig": rig_entry(body.mesh, carried, chosen.suspension),
        "band": band_to_dict(band),
        "elastic": elastic,
        "alternatives": [{"suspension": m.suspension.describe(), "band": band_to_dict(b)} for m, b in others],
    }, fe


def rig_entry(mesh, body, suspension: Suspension) -> dict | None:
    """plan.json's ``rig`` of ``suspension``: a cord's apex and the bridle that holds it (:mod:`.rigging`), or the foam
    pad's contact points (``pads``, m), with a ``description``; None for a free body or a cord no bridle reaches."""
    if suspension.cords:
        rigged = support_rig(mesh, body, suspension.cords[0].attachment)
        return rigged.as_dict() | {"description": rigged.describe()} if rigged else None
    if suspension.foam is not None:
        pads = suspension.foam.points
        where = "; ".join(mm(p) for p in pads[:MOST_PADS_SAID]) + (" …" if len(pads) > MOST_PADS_SAID else "")
        return {"pads": pads.tolist(), "description": f"foam pad under {len(pads)} contact points, at {where} mm"}
    return None


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


def plan_mesh(doc: dict, plan_path: str | Path) -> BodyMesh:
    """The mesh a plan was made on: a bundled name, a path relative to the plan file ``plan_path``'s folder (as
    ``massline plan`` writes it, so that the plan works from any folder and moves with its mesh), or a path as
    given from the current folder (plans written before)."""
    plan_path = Path(plan_path)
    name, units, density = doc.get("mesh"), doc.get("units", "m"), doc.get("density")
    beside, given = plan_path.parent / (name or ""), Path(name or "")
    if name in BUNDLED and not beside.is_file() and not given.is_file():
        return planned_body(load_body(BUNDLED[name].path, "m", density or BUNDLED[name].density), doc)
    for path in (beside, given):
        if name and path.is_file():
            return planned_body(load_body(path, units, density), doc)
    raise MasslineError(
        f"the plan's mesh '{name}' is not at {beside}, where plan.json names it relative to itself: keep the mesh "
        "where it was when planned relative to the plan's folder (move both together), or plan again"
    )


def planned_body(body: BodyMesh, doc: dict) -> BodyMesh:
    """``body``, refused when its mass or CoG is not the plan's ``nominal`` (the mesh was changed or swapped
    since it was planned): checked before any FE work. Named in the plan's length unit."""
    nominal = doc.get("nominal") or {}
    if "mass" not in nominal or "cog" not in nominal:
        return body
    mass, cog = float(nominal["mass"]), np.asarray(nominal["cog"], dtype=float)
    size = float(body.mesh.extents.max())
    if abs(body.nominal.mass - mass) <= MESH_MATCH * mass and np.abs(body.nominal.cog - cog).max() <= MESH_MATCH * size:
        return body
    unit = doc.get("units", "m")
    scale = UNITS.get(unit, 1.0)
    raise MasslineError(
        f"the mesh '{doc.get('mesh')}' is not the body the plan was made on: {body.nominal.mass:.4g} kg with its CoG at "
        f"{vector_text(body.nominal.cog / scale, 4)} {unit} where the plan says {mass:.4g} kg at "
        f"{vector_text(cog / scale, 4)} {unit}: give the plan's mesh, or plan again on this one"
    )
