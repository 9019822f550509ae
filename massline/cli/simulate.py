"""``massline simulate PLAN.json --out FILE.uff``: the virtual test of a plan, as a test system would record it.

By default the file is what a lab's exporter writes: lines + the 0 Hz line, coherence beside every FRF, geometry
in mm (164 code 5) and accelerance in g/N. Accelerometers are calibrated in mV/g and analysers show and export
accelerance in g/N (Testlab, ME'scope "Gs/N"), while the geometry comes from CAD in mm; ``--units``,
``--acceleration``, ``--nodes`` and ``--no-dc`` write the other conventions.

The body hangs on the plan's support (plan.json's ``suspension``; a plan without one: a soft cord above the
CoG) unless ``--suspension`` gives another. Also the pre-test check: where the massline band lies under the
support simulated, by the plan's rule (every FRF within the tolerance of its massline's scale), and the plan's
support when it widens the band (``--check`` stops there). The test is set up and recorded by
:mod:`massline.virtual.simulation`; here: the options, the band table, the plot and the files.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

from rich.console import Console
from rich.table import Table

from massline.cli.options import (
    SEED,
    TRANSVERSE_PRIOR,
    add_calibration_argument,
    add_sensor_mass_argument,
    count,
    fraction,
    positive,
    real,
)
from massline.core.calibration import TRANSVERSE, Calibration
from massline.cli.output import progress_bar, say_fe_model, say_material
from massline.core.band import Band
from massline.core.housing_masses import HousingMasses
from massline.virtual.housing_loading import planned_masses
from massline.core.errors import MasslineError
from massline.core.files import claim_outputs, to_json, write_atomic
from massline.meshes.loader import MAX_MASS_KG
from massline.placement.plan_file import read_plan
from massline.identify.diagnose.effects import effect_help, parse_effect
from massline.uff.units import ACCELERATIONS, UNITS
from massline.uff.writer import run_files, write_runs, write_uff
from massline.virtual.effects import check_targets
from massline.virtual.elastic import MATERIALS
from massline.virtual.measurement import ImpactTest, Noise
from massline.virtual.planned_test import MODES, band_phrase, plan_mesh
from massline.virtual.simulation import record_test, set_up_test
from massline.virtual.suspension import Suspension
from massline.virtual.acquisition import Acquisition
from massline.virtual.analyser import RECORDS

AUTO = -1.0  # --impact without a pulse length: the analyser setup chooses it
MAX_PULSE_MS = 100.0  # a hammer pulse lasts 0.1-10 ms; a soft tip on a heavy body a few tens
MAX_FMAX_HZ = 100_000.0  # an analyser's bandwidth
MIN_LINES, MAX_SPECTRAL_LINES = 16, 102_400  # an analyser's line counts
MAX_MODES = 100  # elastic modes of the FE model


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by 'massline plan'")
    parser.add_argument("--out", metavar="FILE.uff", help="the recording to write (its truth goes to FILE.truth.json)")
    parser.add_argument(
        "--split-runs",
        action="store_true",
        help="write one file per exciter, FILE.run1.uff, FILE.run2.uff, … (a shaker moved between runs), each with "
        "every node; identify and diagnose read them together",
    )
    parser.add_argument("--check", action="store_true", help="only predict the massline band; write no recording")
    parser.add_argument(
        "--seed", type=SEED, default=0, metavar="N", help="seed of noise and effect placement (default 0)"
    )
    parser.add_argument(
        "--noise",
        type=fraction(),
        default=0.01,
        metavar="REL",
        help="relative FRF noise, a fraction of each FRF's level (default 0.01)",
    )
    parser.add_argument(
        "--noise-floor", type=fraction(), default=0.0, metavar="F", help="noise floor, fraction of 1/mass (default 0)"
    )
    parser.add_argument(
        "--suspension",
        metavar="SPEC",
        help="'cord[:k=N/m,L=m,at=X;Y;Z,loss=η]' (a soft 1 m cord tied above the CoG), 'foam[:k=N/m,shear=r]' "
        "or 'none' (free body); default: the plan's support",
    )
    parser.add_argument(
        "--effect",
        action="append",
        default=[],
        metavar="NAME=SIZE@WHERE",
        help=effect_help(),
    )
    add_sensor_mass_argument(
        parser,
        "KG [POINT=KG ...]",
        "mass of each accelerometer housing, kg (a triaxial counts once), then POINT=KG for an accelerometer "
        "whose housing differs (the plan's point labels, e.g. 0.008 1=0.025) (default: the plan's --sensor-mass, "
        "else 0)",
    )
    parser.add_argument(
        "--gauge-mass",
        type=real(0, MAX_MASS_KG, "kg"),
        default=0.0,
        metavar="KG",
        help="a shaker test: the force gauge's structure-side mass riding at each drive point while that exciter "
        "drives (each column its own body; the effect excitation_mass_loading at every exciter), kg (default 0: "
        "none); not with --impact",
    )
    parser.add_argument(
        "--impact",
        type=positive("ms", MAX_PULSE_MS),
        nargs="?",
        const=AUTO,
        metavar="MS",
        help="simulate hammer hits (half-sine pulse of MS ms; without MS the tip an engineer fits to the bandwidth)",
    )
    parser.add_argument(
        "--record",
        choices=RECORDS,
        default="support",
        help="with --impact, what the record is long enough for: the lowest support mode (default; the window adds "
        "≤ 5 %% critical damping to it: 32 s, 25,600 lines for the bracket on its cord) or the band (≥ 100 lines in "
        "it, ≤ 5 %% at its low edge: 1 s, 800 lines, a file 30× smaller; identify then says the support modes are "
        "unresolved)",
    )
    parser.add_argument(
        "--averages",
        type=count(1, 1000),
        default=5,
        metavar="N",
        help="hits averaged per exciter (impact route; default 5)",
    )
    parser.add_argument(
        "--fmax",
        type=positive("Hz", MAX_FMAX_HZ),
        metavar="HZ",
        help="bandwidth (default: 1.5 × first elastic mode; with --impact an analyser bandwidth ≥ 3 × the band's top)",
    )
    parser.add_argument(
        "--lines",
        type=count(MIN_LINES, MAX_SPECTRAL_LINES, "spectral lines"),
        metavar="N",
        help="spectral lines (default 2000; with --impact 400·2^k, a record long enough for the lowest support mode)",
    )
    parser.add_argument(
        "--modes", type=count(1, MAX_MODES), default=MODES, metavar="N", help=f"elastic modes kept (default {MODES})"
    )
    parser.add_argument("--rigid", action="store_true", help="no elastic modes: a rigid body")
    parser.add_argument(
        "--fe-size", type=positive("m", 1.0), metavar="M", help="element size of the FE mesh (default: automatic)"
    )
    parser.add_argument(
        "--material", metavar="NAME|E,NU", help=f"{', '.join(MATERIALS)}, or Young's modulus (Pa) and Poisson's ratio"
    )
    add_chain_arguments(parser)
    add_file_arguments(parser)
    parser.add_argument("--plot", metavar="PNG", help="predicted driving-point FRFs with the band marked")
    parser.add_argument("--force", action="store_true", help="overwrite existing outputs")


def add_chain_arguments(parser: argparse.ArgumentParser) -> None:
    """The measuring chain's errors drawn (:mod:`massline.virtual.chain_errors`): ``--calibration``,
    ``--transverse``, or ``--ideal`` for none."""
    add_calibration_argument(parser, "each channel's and the force transducer's error is drawn from it")
    parser.add_argument(
        "--transverse",
        type=TRANSVERSE_PRIOR,
        default=TRANSVERSE,
        metavar="FRACTION",
        help=f"1-σ of each component of each accelerometer's transverse sensitivity drawn, a fraction (default "
        f"{TRANSVERSE}, identify's prior)",
    )
    parser.add_argument(
        "--ideal",
        action="store_true",
        help="an ideal measuring chain: no calibration error, no transverse sensitivity (the test's noise only)",
    )


def chain_of(args: argparse.Namespace) -> Calibration | None:
    """The chain's 1-σ the test draws its errors from; None with --ideal (refused beside --calibration)."""
    if args.ideal:
        if args.calibration is not None:
            raise MasslineError("--ideal draws no calibration error: drop --calibration or --ideal")
        return None
    return replace(args.calibration or Calibration(), transverse=args.transverse)


def file_units(text: str) -> str:
    """``--units`` as every command spells lengths (m, mm, in; SI too), as dataset 164's system: SI, MM or IN."""
    system = {"m": "SI", "si": "SI", "mm": "MM", "in": "IN"}.get(text.strip().lower())
    if system is None:
        raise argparse.ArgumentTypeError(f"'{text}' is no unit system of the file: give m, mm or in")
    return system


def add_file_arguments(parser: argparse.ArgumentParser) -> None:
    """How the recording is written: records, unit system, acceleration unit, node datasets, the 0 Hz line."""
    parser.add_argument("--binary", action="store_true", help="write FRFs as binary 58b records")
    parser.add_argument(
        "--units",
        type=file_units,
        default="MM",
        metavar="{m,mm,in}",
        help="the file's unit system (dataset 164): m (m, N), mm (mm, mN) or in (in, lbf); default mm",
    )
    parser.add_argument(
        "--acceleration",
        choices=ACCELERATIONS,
        default="g",
        help="accelerance in g per force unit (g/N, or g/lbf with --units in; default) or in length/s² per force",
    )
    parser.add_argument(
        "--nodes",
        type=int,
        choices=(15, 2411),
        default=15,
        help="nodes in dataset 15 (+18) or 2411 (+2420) (default 15)",
    )
    parser.add_argument("--no-dc", action="store_true", help="start the axis at Δf, without the exporter's 0 Hz line")
    parser.add_argument(
        "--setup-systems",
        action="store_true",
        help="every node in a coordinate system of its own, each lone line its +Z, as 'massline setup' writes them",
    )


def band_table(rows: list[tuple[str, Band, Suspension]]) -> Table:
    table = Table(title="Predicted massline band (every FRF within the tolerance of its massline's scale)")
    for col in ("suspension", "top susp. mode (Hz)", "band (Hz)", "every FRF within", "1st elastic (Hz)", "width"):
        table.add_column(col, justify="right")
    for name, band, _ in rows:
        width = f"{band.ratio:.1f}×" if band.exists else "no band"
        span = f"{band.low:.1f} – {band.high:.1f}" if band.exists else "—"
        within = f"{100 * band.tolerance:g} %"
        table.add_row(name, f"{band.suspension_top:.2f}", span, within, f"{band.first_elastic:.1f}", width)
    return table


def sensor_masses(args: argparse.Namespace, doc: dict) -> HousingMasses:
    """The housings the test carries: ``--sensor-mass``'s, else the plan's (plan.json's ``loading``)."""
    return HousingMasses.parse(args.sensor_mass) if args.sensor_mass else planned_masses(doc)


def departures(args: argparse.Namespace, doc: dict) -> str:
    """The options that make this test differ from the one plan.json predicted its band for."""
    given = {
        "--suspension": args.suspension,
        "--sensor-mass": sensor_masses(args, doc) != planned_masses(doc),
        "--gauge-mass": args.gauge_mass,
        "--rigid": args.rigid,
        "--modes": args.modes != MODES,
        "--fe-size": args.fe_size,
        "--material": args.material,
    }
    return ", ".join(name for name, value in given.items() if value)


def run(args: argparse.Namespace, console: Console) -> None:
    plan_path = Path(args.plan)
    sensors, exciters, doc = read_plan(plan_path)
    if not args.check and not args.out:
        raise MasslineError("give --out FILE.uff for the recording, or --check for the band prediction only")
    if args.record != "support" and args.impact is None:
        raise MasslineError("--record sets an impact test's record: give --impact, or drop --record")
    named = {} if args.check else recording_outputs(Path(args.out), len(exciters) if args.split_runs else 0)
    outputs = claim_outputs(named | {"--plot": args.plot}, args.force)
    chain_of(args)  # refused before the work
    effects = tuple(parse_effect(e) for e in args.effect) + gauge_effects(args)
    check_targets(list(effects), len(sensors), len(exciters), args.fmax, args.lines)
    body = plan_mesh(doc, plan_path)
    housings = sensor_masses(args, doc)
    options = {"suspension": args.suspension, "sensor_mass": housings, "rigid": args.rigid}
    options |= {"n_modes": args.modes, "fe_size": args.fe_size, "material": args.material}
    with progress_bar(console) as progress:
        setup = set_up_test(doc, sensors, exciters, body, progress=progress, **options)
        if setup.fe is not None:
            say_material(console, setup.fe, option=True)
    if setup.fe is not None:
        say_fe_model(console, setup.fe)
    console.print(band_table(list(setup.rows)))
    expected = setup.expected
    if expected is not None and departures(args, doc):
        console.print(
            f"plan.json predicts {band_phrase(expected)} for {setup.planned_support.describe()} on the bare body; "
            f"this test departs from it ({departures(args, doc)}), so its band is predicted again above",
            soft_wrap=True,
        )
    if args.plot:
        from massline.reports.figures import driving_point_figure

        cases = [(name, model, band) for (name, band, _), model in zip(setup.rows, setup.models())]
        write_atomic(args.plot, driving_point_figure(cases, exciters), args.force)
        console.print(f"wrote {args.plot}")
    if args.check:
        return
    recording, truth = record_test(setup, effects, acquisition(args, housings), args.seed, plan_path)
    for warning in truth["warnings"]:
        console.print(f"warning: {warning}", markup=False, soft_wrap=True)
    options = {"binary": args.binary, "nodes_dataset": args.nodes, "units": args.units}
    options |= {"setup_systems": args.setup_systems}
    options |= {"acceleration": args.acceleration, "force": args.force}
    if args.split_runs:
        written = write_runs(args.out, recording, **options)
        each = f"one file per exciter: {len(sensors)} FRFs each"
        files = f"{written[0]} … {written[-1].name} ({megabytes(written)}, {each}"
    else:
        write_uff(outputs[0], recording, **options)
        files = f"{outputs[0]} ({megabytes([outputs[0]])}, {len(sensors)} × {len(exciters)} FRFs"
    truth_file = named["the truth file"]
    write_atomic(truth_file, to_json(truth), args.force)
    console.print(
        f"wrote {files} and their coherence, {recording_axis(truth)}, {frf_units(args)}) and {truth_file} (what "
        f"was simulated, including {len(effects)} concealed effect{'s' if len(effects) != 1 else ''} and "
        f"{chain_phrase(truth['chain'])})"
    )


def chain_phrase(chain: dict | None) -> str:
    """'the chain's errors drawn (accelerometers 1 %, force 1 %, transverse 3 % 1-σ)', or 'an ideal chain'."""
    if chain is None:
        return "an ideal measuring chain"
    c = chain["calibration"]
    return (
        f"the chain's errors drawn: accelerometers {100 * c['sensor']:g} %, force {100 * c['force']:g} % (this "
        f"test's force gauge reads {100 * chain['force_gain_error']:+.2f} %), transverse {100 * c['transverse']:g} % "
        "1-σ"
    )


def recording_outputs(out: Path, runs: int) -> dict:
    """The files ``simulate --out OUT`` writes, by what names them: the recording (or each run's file, ``runs`` of
    them with ``--split-runs``), then the truth file."""
    recordings = {f"run {j + 1} of --out": path for j, path in enumerate(run_files(out, runs))} if runs else {}
    return (recordings or {"--out": out}) | {"the truth file": out.with_suffix(".truth.json")}


def gauge_effects(args: argparse.Namespace) -> tuple:
    """``--gauge-mass``'s effect (the gauge at every drive point), refused with ``--impact`` (a hammer has none)."""
    if not args.gauge_mass:
        return ()
    if args.impact is not None:
        raise MasslineError("--gauge-mass is a shaker's force gauge: a hammer test (--impact) has none; drop one")
    return (parse_effect(f"excitation_mass_loading={args.gauge_mass!r}@all"),)


def acquisition(args: argparse.Namespace, housings: HousingMasses) -> Acquisition:
    """The test as the options set it up, carrying ``housings``; what they leave out is chosen as a lab would
    (virtual.analyser)."""
    impact = None
    if args.impact is not None:
        pulse = None if args.impact == AUTO else args.impact * 1e-3
        impact = ImpactTest(pulse=pulse, averages=args.averages, record=args.record)
    return Acquisition(
        fmax=args.fmax,
        lines=args.lines,
        noise=Noise(args.noise, args.noise_floor),
        impact=impact,
        sensor_mass=housings,
        dc_line=not args.no_dc,
        chain=chain_of(args),
    )


def megabytes(paths) -> str:
    """'28.0 MB': what the files written take on disk."""
    return f"{sum(Path(p).stat().st_size for p in paths) / 1e6:.3g} MB"


def recording_axis(truth: dict) -> str:
    """'12800 lines + DC to 400 Hz (T = 32 s, 1.2 ms pulse)': the analyser setup as simulated."""
    text = f"{truth['lines']} lines{' + DC' if truth['dc_line'] else ''} to {truth['fmax_hz']:g} Hz"
    text += f" (T = {truth['record_s']:.3g} s"
    return text + (f", {truth['impact']['pulse'] * 1e3:.2g} ms pulse)" if truth["impact"] else ")")


def frf_units(args: argparse.Namespace) -> str:
    """'geometry in mm, accelerance in g/N': what the file's readers will see."""
    system = UNITS[args.units]
    force = system.g_force_label if args.acceleration == "g" else system.force_label
    top = "g" if args.acceleration == "g" else f"({system.length_label}/s²)"
    return f"geometry in {system.length_label}, accelerance in {top}/{force}"
