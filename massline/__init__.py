"""massline: plan and evaluate the modal test that identifies a body's mass, CoG and inertia tensor.

The package is the test's data flow, one sub-package per stage; each imports only the ones below it
(docs/development.md, "Layout"):

- ``massline`` (this folder): the public API below, re-exported, and ``python -m massline``.
- :mod:`massline.cli`: the command ``massline`` — argument parsing, console output, exit codes; no science.
- :mod:`massline.reports`: HTML pages, scenes, renderings and figures, each report's assembly, the demo's story.
- :mod:`massline.identify`: recordings → masslines → properties; :mod:`massline.identify.diagnose`,
  the mismatch diagnosis.
- :mod:`massline.virtual`: the virtual test (FE modes and their cache, suspension, the planned test,
  instrumentation, measurement, simulation).
- :mod:`massline.uff`: Universal Files read and written, and the ``Recording`` type.
- :mod:`massline.placement`: the pre-test planner.
- :mod:`massline.export`: the measured body (``Body``) in the formats of the tools that use it (Nastran,
  Abaqus, Adams, URDF, SDF, MuJoCo, CSV).
- :mod:`massline.core`: the kernel — lines, rigid-body algebra, the paper's methods, properties, errors;
  it imports nothing else of the project.
- :mod:`massline.meshes`: the bundled bodies and the mesh loader.

The public API, every pipeline a script can call (``from massline import plan_test, simulate_test, ...``), is
imported when first used (PEP 562), so that importing ``massline`` or one of its stages loads nothing else.
"""

from __future__ import annotations

from importlib import import_module

PUBLIC = {  # name: the module defining it
    "__version__": "massline.core",
    "Band": "massline.core",
    "Lines": "massline.core",
    "MasslineError": "massline.core",
    "RigidBody": "massline.core",
    "Body": "massline.export",
    "Calibration": "massline.core.calibration",
    "BUNDLED": "massline.meshes",
    "load_body": "massline.meshes.loader",
    "Recording": "massline.uff.recording",
    "read_uff": "massline.uff.reader",
    "to_recording": "massline.uff.grid",
    "write_uff": "massline.uff.writer",
    "Budget": "massline.placement.planner",
    "plan_layout": "massline.placement.on_surface",
    "cheapest_diagnosable": "massline.placement.diagnosable_plan",
    "plan_to_dict": "massline.placement.plan_file",
    "plan_next_run": "massline.placement.next_run",
    "Measured": "massline.placement.next_run",
    "measured_layout": "massline.identify.measured_layout",
    "read_plan": "massline.placement.plan_file",
    "export_setup": "massline.placement.setup_export",
    "plan_test": "massline.virtual.planned_test",
    "plan_mesh": "massline.virtual.planned_test",
    "fe_model": "massline.virtual.planned_test",
    "simulate_test": "massline.virtual.simulation",
    "set_up_test": "massline.virtual.simulation",
    "record_test": "massline.virtual.simulation",
    "Acquisition": "massline.virtual.acquisition",
    "identify_recording": "massline.identify.pipeline",
    "diagnose_recording": "massline.identify.diagnose.pipeline",
    "build_placement_report": "massline.reports.placement_assembly",
    "identify_report": "massline.reports.identification_report",
    "diagnose_report": "massline.reports.diagnosis_report",
    "demo_story": "massline.reports.demo_story",
}
# exported names that differ from the defining module's (``massline.cli.plan`` is a command)
RENAMED = {"plan_layout": "plan"}

__all__ = sorted(PUBLIC)


def __getattr__(name: str):
    """The public name ``name``, imported from its module on first use and kept."""
    if name not in PUBLIC:
        raise AttributeError(f"module 'massline' has no attribute {name!r}")
    value = getattr(import_module(PUBLIC[name]), RENAMED.get(name, name))
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(PUBLIC))
