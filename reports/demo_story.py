"""The demo's story on the bundled 3-D structure, written into one folder.

Plan a test with room to spare (14 accelerometers, 4 hits) and the support it hangs on, simulate it as a
careful lab would record it (FE modes, the planned support, 1 % noise, every channel a little sensitive across
its axis) with one fault concealed in it, write the UFF, identify the properties from the file alone, diagnose
it with the planned band and the mesh, and write the plan, the placement report, the identification report and
the diagnosis report. The story never reads what was concealed (``truth.json`` keeps it for the reader).

``progress(stage, done, total)``, when given, is called as each of the eight steps starts (``done`` steps
finished of ``total``) and once at the end; None is silent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from massline.core.band import Band
from massline.core.files import claim_folder, to_json, write_atomic
from massline.core.rigid_body import RigidBody
from massline.identify.diagnose.effects import BY_NAME
from massline.identify.diagnose.diagnosis_run import DiagnosisRun
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import Identification, identify_recording
from massline.meshes import BUNDLED
from massline.meshes.loader import BodyMesh, load_body
from massline.placement.on_surface import plan
from massline.placement.plan_file import plan_to_dict
from massline.placement.planner import Budget
from massline.placement.plans import Plan
from massline.reports.placement_assembly import build_placement_report
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.recording import Recording
from massline.uff.writer import write_uff
from massline.virtual.planned_test import plan_test, planned_band, planned_suspension
from massline.virtual.scenarios import Bench, scenario
from massline.virtual.suspension import Suspension

BODY = "structure"
BUDGET = Budget(sensors=14, exciters=4)  # 14 channels for 10 parameters: room to tell a faulty channel
BANDWIDTH = 2.5  # the recording reaches the first elastic mode / BANDWIDTH
FAULT, SEED = "sensor_gain", 3
STEPS = 8
FILES = {
    "plan": "plan.json",
    "placement": "placement-report.html",
    "uff": "test.uff",
    "truth": "truth.json",
    "identification": "identification-report.html",
    "diagnosis": "diagnosis-report.html",
}


@dataclass(frozen=True, eq=False)
class DemoStory:
    """What the demo planned, simulated, identified and diagnosed, and where it wrote it.

    Attributes
    ----------
    paths : dict
        The files written, by the keys of ``FILES``.
    mesh : BodyMesh
        The bundled body (its ``nominal`` properties: kg, m, kg·m²).
    planned : Plan
        The layout planned.
    support : Suspension
        The support the plan chose.
    band : Band
        The band it predicts (Hz).
    first_elastic : float
        The FE model's first elastic frequency, Hz.
    fmax : float
        The recording's bandwidth, Hz.
    recording : Recording
        The test simulated (as written; ``truth`` says what was concealed in it).
    truth : dict
        What was simulated, the concealed fault included.
    identified : Identification
        identify's result on the file read back.
    diagnosis : DiagnosisRun
        The diagnosis of the file read back, with identify's band and the mesh's properties.
    """

    paths: dict
    mesh: BodyMesh
    planned: Plan
    support: Suspension
    band: Band
    first_elastic: float
    fmax: float
    recording: Recording
    truth: dict
    identified: Identification
    diagnosis: DiagnosisRun

    @property
    def nominal(self) -> RigidBody:
        """The mesh's properties."""
        return self.mesh.nominal


def demo_band(band) -> tuple[float, float] | None:
    """The planned band (Hz) the scenario passes on, or None when the plan predicts none."""
    return (band.low, band.high) if band.exists else None


def demo_story(
    folder: str | Path, *, fault: str = FAULT, seed: int = SEED, force: bool = False, progress=None
) -> DemoStory:
    """Tell the demo's story into ``folder`` (created; its files refused before any work when one exists and
    not ``force``): ``fault`` (a fault of :data:`massline.virtual.scenarios.FAULTS`) concealed, its size and
    place drawn from ``seed``."""
    from massline.reports.diagnosis_report import diagnose_report  # matplotlib: loaded when the story is told
    from massline.reports.identification_report import identify_report

    folder = Path(folder)
    paths = dict(zip(FILES, claim_folder(folder, FILES.values(), force)))
    folder.mkdir(parents=True, exist_ok=True)
    steps = iter(range(STEPS + 1))

    def step(text: str) -> None:
        done = next(steps)
        if progress is not None:
            progress(text, done, STEPS)

    step(f"1/8 planning {BUDGET.sensors} accelerometers and {BUDGET.exciters} hits")
    mesh = load_body(BUNDLED[BODY].path, "m", BUNDLED[BODY].density)
    nominal = mesh.nominal
    planned = plan(mesh, BUDGET)
    step("2/8 the support and its band: FE model of the structure, every FRF against its massline")
    test, fe = plan_test(mesh, BODY, planned.sensors, planned.exciters)
    modes = fe.modes
    doc = plan_to_dict(planned, BODY, "m", mesh.density, test)
    write_atomic(paths["plan"], to_json(doc), force)
    band, support = planned_band(doc), planned_suspension(doc)
    step("3/8 placement report: views")
    write_atomic(paths["placement"], build_placement_report(paths["plan"]).html, force)
    step(f"4/8 simulating the test with a concealed fault ({fault})")
    fmax = modes.frequencies_hz[0] / BANDWIDTH
    bench = Bench(nominal, planned.sensors, planned.exciters, modes, fmax, support=support, band=demo_band(band))
    recording, truth = scenario(bench, fault, seed, effects=BY_NAME)
    write_uff(paths["uff"], recording, force=force)
    write_atomic(paths["truth"], to_json(truth), force)
    step("5/8 identify: band, band fits, estimate, bootstrap")
    read = to_recording(read_uff(paths["uff"]))  # from here on the story sees the file only
    identified = identify_recording(read)
    step("6/8 identification report")
    write_atomic(paths["identification"], identify_report(identified, paths["uff"], mesh).html, force)
    step("7/8 diagnose: identify's band and the mesh")
    diagnosis = diagnose_recording(read, None, nominal)  # identify's band, so "before" is identify's result
    step("8/8 diagnosis report")
    write_atomic(paths["diagnosis"], diagnose_report(diagnosis, paths["uff"], mesh).html, force)
    step("done")
    first = float(modes.frequencies_hz[0])
    return DemoStory(paths, mesh, planned, support, band, first, bench.fmax, recording, truth, identified, diagnosis)
