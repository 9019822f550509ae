"""The virtual test of a plan: the body with its accelerometers on, hung on its support, its band predicted, recorded.

The body hangs on the plan's support (plan.json's ``suspension``; a plan without one: a soft cord above the CoG)
unless another is given. Before anything is recorded, the band the test will have is predicted by the plan's
rule (every FRF within the tolerance of its massline's scale), with the plan's support beside a given one when
it widens the band (:func:`set_up_test`); then the test is recorded as a test system would
(:func:`record_test`). :func:`simulate_test` does both. Writing the recording is the caller's.

``progress(stage, done, total)``, when given, is called over the FE solve
(:mod:`massline.virtual.planned_test`); None is silent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from massline.core.housing_masses import HousingMasses
from massline.core.band import Band
from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.meshes.loader import BodyMesh
from massline.uff.recording import Recording
from massline.virtual.acquisition import Acquisition, accelerometer_masses
from massline.virtual.acquisition import run as run_test
from massline.virtual.attachment import point_above
from massline.virtual.band_prediction import predict_band, recommend_suspension
from massline.core.effect_names import SimulatedEffect
from massline.virtual.planned_test import (
    MODES,
    FEModel,
    assumed_material,
    body_material,
    fe_model,
    planned_band,
    planned_suspension,
)
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension, hung_over
from massline.virtual.tetmesh import size_for_dofs

MAX_FE_DOFS = 200_000  # the finest FE model an element size may ask for (a few GB to assemble and solve)


@dataclass(frozen=True, eq=False)
class TestSetup:
    """A virtual test set up, before anything is recorded.

    Attributes
    ----------
    nominal, loaded : RigidBody
        The bare body and the body with its accelerometers on (kg, m, frame O xyz).
    sensors, exciters : Lines
        The plan's accelerometer and hit lines (m).
    suspension : Suspension
        The support simulated.
    planned_support : Suspension or None
        The support plan.json keeps (None: an older plan).
    expected : Band or None
        The band plan.json predicts for its support on the bare body (None: an older plan).
    fe : FEModel or None
        The FE model's elastic modes (None: a rigid body).
    model : SuspendedBody
        The suspended body with its accelerometers on, as simulated.
    rows : tuple of (str, Band, Suspension)
        The predicted band under the support simulated ("planned: …"), then under the plan's (or a recommended)
        support when that one is wider ("recommended: …").
    mesh_name, units : str or None
        The plan's mesh and its units, kept in the truth.
    """

    nominal: RigidBody
    loaded: RigidBody
    sensors: Lines
    exciters: Lines
    suspension: Suspension
    planned_support: Suspension | None
    expected: Band | None
    fe: FEModel | None
    model: SuspendedBody
    rows: tuple
    mesh_name: str | None = None
    units: str | None = None

    @property
    def modes(self):
        """The elastic modes, or None for a rigid body."""
        return None if self.fe is None else self.fe.modes

    def models(self) -> list[SuspendedBody]:
        """The suspended body (accelerometers on) under each support of :attr:`rows`."""
        planned = self.model
        masses, points = planned.masses, planned.mass_points
        return [SuspendedBody(self.nominal, self.modes, s, masses, points) for _, _, s in self.rows]


@dataclass(frozen=True, eq=False)
class Simulation:
    """A virtual test: its setup, the recording and the truth (what was simulated, JSON-ready)."""

    setup: TestSetup
    recording: Recording
    truth: dict


def simulated_support(spec: str | None, planned: Suspension | None, mesh, loaded: RigidBody) -> Suspension:
    """The support simulated: ``spec``'s (:meth:`Suspension.parse`), else the plan's hung above the CoG with the
    accelerometers on, else (a plan that keeps none) a soft cord above the CoG."""
    if spec is None and planned is not None:
        return hung_over(planned, loaded.cog)
    return Suspension.parse(spec or "cord", mesh, loaded)


def loaded_body(nominal: RigidBody, housings: tuple, mass: float | HousingMasses) -> RigidBody:
    """The body with its accelerometers on (what the supports carry and hold level); refused when they
    would outweigh it."""
    masses, _ = housings
    if masses.sum() >= nominal.mass:
        given = mass.describe() if isinstance(mass, HousingMasses) else f"{mass:g} kg each"
        raise MasslineError(
            f"--sensor-mass ({given}): {len(masses)} accelerometers would weigh {masses.sum():.3g} kg, as much "
            f"as the body ({nominal.mass:.3g} kg): give each housing's mass in kg, below "
            f"{nominal.mass / len(masses):.3g}"
        )
    return SuspendedBody(nominal, None, Suspension(), *housings).loaded


def check_fe_size(size: float | None, body: BodyMesh) -> None:
    """An element size (m) no finer than that of MAX_FE_DOFS degrees of freedom on this body."""
    finest = size_for_dofs(body.mesh, MAX_FE_DOFS)
    if size is not None and size < finest:
        raise MasslineError(
            f"--fe-size {size:g}: elements this small would give this body more than {MAX_FE_DOFS} FE degrees of "
            f"freedom (hours and tens of GB): give 0 < M ≤ 1 m, at least {finest:.3g} m"
        )


def band_advice(planned: SuspendedBody, given: bool, plan_support, mesh, sensors, exciters) -> tuple:
    """The band under the support simulated, then, for a ``given`` support, under the plan's (or one recommended
    above the CoG) when that one is wider: rows (name, Band, Suspension)."""
    suspension, loaded = planned.suspension, planned.loaded
    rows = [("planned: " + suspension.describe(), predict_band(planned, sensors, exciters), suspension)]
    if given and not suspension.is_free:
        advice = simulated_support(None, plan_support, None, loaded) if plan_support else None
        advice = advice or recommend_suspension(planned, point_above(mesh, loaded.cog)[0])
        advised = SuspendedBody(planned.body, planned.modes, advice, planned.masses, planned.mass_points)
        band = predict_band(advised, sensors, exciters, rows[0][1].tolerance)
        if band.wider_than(rows[0][1]):
            rows.append(("recommended: " + advice.describe(), band, advice))
    return tuple(rows)


def set_up_test(
    doc: dict,
    sensors: Lines,
    exciters: Lines,
    body: BodyMesh,
    *,
    suspension: str | None = None,
    sensor_mass: float | HousingMasses = 0.0,
    rigid: bool = False,
    n_modes: int = MODES,
    fe_size: float | None = None,
    material: str | None = None,
    progress=None,
) -> TestSetup:
    """Set up the virtual test of a plan: the loaded body, its support, its FE modes and the band advice.

    Parameters
    ----------
    doc : dict
        plan.json's document (its ``suspension``, ``band``, ``mesh`` and ``units`` are read).
    sensors, exciters : Lines
        The plan's lines (m).
    body : BodyMesh
        The plan's body (:func:`massline.virtual.planned_test.plan_mesh`).
    suspension : str, optional
        A support (:meth:`Suspension.parse`'s spec) instead of the plan's.
    sensor_mass : float or HousingMasses
        Mass of each accelerometer, kg, or per point label (the plan's numbering; a triaxial counts once).
    rigid : bool
        No elastic modes.
    n_modes : int
        Elastic modes of the FE model.
    fe_size : float, optional
        Element size of the FE mesh, m (default: automatic).
    material : str, optional
        A material name or 'E,NU' (Pa, dimensionless); default: the bundled body's or the closest-density metal.
    progress : callable, optional
        ``progress(stage, done, total)`` over the FE solve.
    """
    nominal = body.nominal
    housings = accelerometer_masses(sensors, sensor_mass)
    loaded = loaded_body(nominal, housings, sensor_mass)
    plan_support = planned_suspension(doc)
    support = simulated_support(suspension, plan_support, body.mesh, loaded)
    if not support.is_free:
        support.reactions(loaded)  # a support that cannot carry the body is refused before the FE work
    check_fe_size(fe_size, body)
    fe = None
    if not rigid:
        name = doc.get("mesh")
        chosen = body_material(body, name, material)
        assumed = assumed_material(body, name, material)
        fe = fe_model(body, chosen, size=fe_size, n=n_modes, progress=progress, assumed=assumed)
    planned = SuspendedBody(nominal, None if fe is None else fe.modes, support, *housings)
    rows = band_advice(planned, suspension is not None, plan_support, body.mesh, sensors, exciters)
    expected = planned_band(doc)
    return TestSetup(
        nominal, loaded, sensors, exciters, support, plan_support, expected, fe, planned, rows, doc.get("mesh"),
        doc.get("units"),
    )


def record_test(
    setup: TestSetup,
    effects: tuple[SimulatedEffect, ...] = (),
    acquisition: Acquisition | None = None,
    seed: int = 0,
    plan_path: str | Path | None = None,
) -> tuple[Recording, dict]:
    """Record the test set up (:mod:`massline.virtual.acquisition`) with ``effects`` concealed; return the
    recording and the truth, which also keeps the plan (``plan_path``), its mesh and units, and the FE model."""
    recording, truth = run_test(
        setup.nominal, setup.sensors, setup.exciters, setup.modes, setup.suspension, effects, acquisition, seed
    )
    truth |= {"plan": None if plan_path is None else str(plan_path), "mesh": setup.mesh_name, "units": setup.units}
    if setup.fe is not None:
        truth["fe"] = {
            "youngs": setup.fe.material.youngs,
            "poisson": setup.fe.material.poisson,
            "dofs": setup.fe.modes.n_dofs,
            "element_size": setup.fe.modes.element_size,
        }
    return recording, truth


def simulate_test(
    doc: dict,
    sensors: Lines,
    exciters: Lines,
    body: BodyMesh,
    *,
    effects: tuple[SimulatedEffect, ...] = (),
    acquisition: Acquisition | None = None,
    seed: int = 0,
    plan_path: str | Path | None = None,
    suspension: str | None = None,
    rigid: bool = False,
    n_modes: int = MODES,
    fe_size: float | None = None,
    material: str | None = None,
    progress=None,
) -> Simulation:
    """The virtual test of a plan (:func:`set_up_test`, then :func:`record_test`; the accelerometers' mass is
    ``acquisition.sensor_mass``, kg). Parameters as theirs; nothing is written."""
    acquisition = acquisition or Acquisition()
    options = {"suspension": suspension, "rigid": rigid, "n_modes": n_modes, "fe_size": fe_size, "material": material}
    setup = set_up_test(doc, sensors, exciters, body, sensor_mass=acquisition.sensor_mass, progress=progress, **options)
    return Simulation(setup, *record_test(setup, effects, acquisition, seed, plan_path))
