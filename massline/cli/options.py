"""Option values checked where they are parsed.

Each factory returns an argparse ``type=`` function: it gives back the value or raises
``argparse.ArgumentTypeError`` with the allowed range and its unit, and argparse puts the option's
name in front ("argument --noise: ..."). ``Parser`` prints that as one line, exit code 2, before any
work starts.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Callable

from massline.core.calibration import FORCE_CALIBRATION, SENSOR_CALIBRATION, Calibration
from massline.core.errors import MasslineError
from massline.core.files import claim_outputs
from massline.core.housing_masses import parse_exciter_mass, sensor_mass_token
from massline.export import FORMATS, UNITS, check_export, format_of
from massline.meshes.loader import MAX_MASS_KG, PLAUSIBLE_DENSITY

SEED_MAX = 2**32 - 1  # numpy's seeds

# The library's parameters (core/errors.py ``param``) as the command line names them: a library error is
# printed with these flags (``MasslineError.spelled(FLAGS)``), its value after the flag.
FLAGS = {
    "band": "--band",
    "budget.exciters": "--exciters",
    "budget.sensors": "--sensors",
    "budget.triaxial": "--triaxial",
    "calibration": "--calibration",
    "density": "--density",
    "effect": "--effect",
    "folder": "--out",
    "force": "--force",
    "mass": "--mass",
    "material": "--material",
    "method": "--method",
    "minimal_budget": "--minimal",
    "nodes_dataset": "--nodes",
    "options.axes": "--axes",
    "options.edge_keepout": "--edge-keepout",
    "options.hammer_tip": "--tip",
    "options.n_samples": "--candidates",
    "options.sensor_base": "--sensor-base",
    "sensor_mass": "--sensor-mass",
    "exciter_mass": "--exciter-mass",
    "size": "--fe-size",
    "suspension": "--suspension",
    "units": "--units",
    "weighed": "--weighed-mass",
}


NEGATIVE = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^-(?:inf|infinity|nan)$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line (no usage block), exit code 2, and that reads '-1e3' and
    '-inf' as values (argparse takes them for options), so that they meet the option's range check."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE

    def error(self, message: str):
        text = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {text} (see '{self.prog} --help')\n")


def _shown(value: float) -> str:
    """2000000 as '2000000', 0.5 as '0.5', 1e6 Hz as '1000000'."""
    return str(int(value)) if value == int(value) and abs(value) < 1e15 else f"{value:g}"


def range_text(low: float, high: float, unit: str, low_open: bool = False) -> str:
    """'0 ≤ value ≤ 1 (fraction)' or '0 < value (kg)': the allowed values, in words a user reads."""
    left = "" if low == -math.inf else f"{_shown(low)} {'<' if low_open else '≤'} "
    right = "" if high == math.inf else f" ≤ {_shown(high)}"
    return f"{left}value{right}" + (f" ({unit})" if unit else "")


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None


def real(
    low: float = -math.inf,
    high: float = math.inf,
    unit: str = "",
    low_open: bool = False,
    hint: Callable[[float], str] | None = None,
) -> Callable[[str], float]:
    """A finite number in [low, high] (``low`` excluded when ``low_open``), in ``unit``; ``hint(value)`` adds a
    guess at the user's slip to the refusal."""
    allowed = range_text(low, high, unit, low_open)

    def parse(text: str) -> float:
        value = _float(text)
        inside = (low < value if low_open else low <= value) and value <= high
        if not (math.isfinite(value) and inside):
            extra = hint(value) if hint and math.isfinite(value) else ""
            raise argparse.ArgumentTypeError(f"{text} is out of range: give a finite {allowed}{extra}")
        return value

    parse.__name__ = "number"
    return parse


def positive(unit: str, high: float = math.inf) -> Callable[[str], float]:
    """A number > 0 (and ≤ ``high``) in ``unit``."""
    return real(0.0, high, unit, low_open=True)


def fraction(high: float = 1.0, low_open: bool = False) -> Callable[[str], float]:
    """A fraction in [0, high] (or (0, high])."""
    return real(0.0, high, "fraction, e.g. 0.01 for 1 %", low_open=low_open)


def count(low: int, high: int, unit: str = "") -> Callable[[str], int]:
    """A whole number in [low, high]; '1e5' is read as 100000."""
    allowed = range_text(low, high, unit)

    def parse(text: str) -> int:
        value = _float(text)
        if not (math.isfinite(value) and value == int(value) and low <= value <= high):
            raise argparse.ArgumentTypeError(f"{text} is out of range: give a whole number {allowed}")
        return int(value)

    parse.__name__ = "count"
    return parse


def finite(unit: str) -> Callable[[str], float]:
    """Any finite number (a coordinate) in ``unit``."""
    return real(unit=unit)


def checked(parse: Callable[[str], object]) -> Callable[[str], object]:
    """A parser raising MasslineError, as an argparse type (its message kept, parameters named by their flags)."""

    def wrapped(text: str):
        try:
            return parse(text)
        except MasslineError as error:
            raise argparse.ArgumentTypeError(error.spelled(FLAGS)) from None

    wrapped.__name__ = getattr(parse, "__name__", "value")
    return wrapped


def _grams_per_cc(value: float) -> str:
    return f"; was it in g/cm³? (then pass {value * 1000:g})" if 0 < value < PLAUSIBLE_DENSITY[0] else ""


DENSITY = real(*PLAUSIBLE_DENSITY, "kg/m³, from rigid foams to tungsten alloys", hint=_grams_per_cc)
MASS = positive("kg", MAX_MASS_KG)
SEED = count(0, SEED_MAX)
BAND_EDGE = positive("Hz", 1e6)
TRANSVERSE_PRIOR = fraction(0.5)  # a 1-σ beyond 50 % of the main axis' sensitivity is no accelerometer
MAX_DRAWS = 10_000  # bootstrap draws: beyond this the ± no longer changes, the wait does


def add_recording_argument(parser: argparse.ArgumentParser) -> None:
    """The recording: one Universal File, or one per run (or a folder of them)."""
    parser.add_argument(
        "uff",
        nargs="+",
        metavar="FILE.uff",
        help="FRFs exported by the test software (UFF 58/58b): one file, or one file per run, or a folder of "
        "them (merged by node label; pairs measured in several runs are averaged, pairs not measured left out)",
    )


def source_of(paths: list[str]) -> str:
    """How a recording given as ``paths`` is named in titles and notes: the file, or the first and how many."""
    return paths[0] if len(paths) == 1 else f"{paths[0]} + {len(paths) - 1} more"


def check_band(band: list[float] | None) -> None:
    """``--band LO HI``: LO below HI (each already a positive frequency in Hz)."""
    if band is not None and not band[0] < band[1]:
        raise MasslineError(f"--band {band[0]:g} {band[1]:g}: give LO < HI, both in Hz (e.g. --band 5 40)")


EXPORT_FLAGS = {"units": "--export-units", "path": "--export"}  # the export library's parameters, as flags here


def export_path(text: str) -> str:
    """``--export FILE``: a file whose suffix names an export format (the path itself is checked in ``run``)."""
    format_of(text)
    return text


def add_export_arguments(parser: argparse.ArgumentParser) -> None:
    """``--export FILE`` (repeatable), ``--export-units`` and ``--export-as-tested``: identify's and diagnose's."""
    parser.add_argument(
        "--export",
        action="append",
        default=[],
        type=checked(export_path),
        metavar="FILE",
        help=f"write the body for the tool that uses it, the format from the suffix ({', '.join(FORMATS)}: Nastran, "
        "Nastran, Abaqus, Adams, URDF, SDFormat, MuJoCo, CSV); repeatable",
    )
    parser.add_argument(
        "--export-units",
        choices=list(UNITS),
        default="m-kg",
        help="lengths and masses of --export files (default m-kg; URDF, SDF and MuJoCo take m-kg only)",
    )
    parser.add_argument(
        "--export-as-tested",
        action="store_true",
        help="export the body as tested, with the accelerometer (or loading) masses on, not the bare body",
    )


def claim_exports(args: argparse.Namespace, others: dict) -> None:
    """Before any work: every ``--export`` file's format takes ``--export-units`` and may be written, and no two
    outputs (``others``: {option: path} of the command's other files) name one file."""
    try:
        for path in args.export:
            check_export(path, args.export_units, args.force)
    except MasslineError as error:
        raise MasslineError(error.spelled(FLAGS | EXPORT_FLAGS)) from None
    claim_outputs([*others.items(), *(("--export", path) for path in args.export)], args.force)


def add_sensor_mass_argument(parser: argparse.ArgumentParser, metavar: str, help: str) -> None:
    """``--sensor-mass KG [LABEL=KG ...]`` (plan, simulate, identify, diagnose): each accelerometer housing's mass,
    the default first, each token checked as it is read (:meth:`HousingMasses.parse` reads the list)."""
    parser.add_argument(
        "--sensor-mass", nargs="+", type=checked(sensor_mass_token), default=[], metavar=metavar, help=help
    )


def add_calibration_argument(parser: argparse.ArgumentParser, role: str) -> None:
    """``--calibration SENSOR[,FORCE]``: the chain's calibration 1-σ in per cent (:mod:`massline.core.calibration`);
    ``role`` says what the command does with it."""
    parser.add_argument(
        "--calibration",
        type=checked(Calibration.parse),
        metavar="SENSOR[,FORCE]",
        help=f"1-σ of each accelerometer's and of the force transducer's calibration, per cent (default "
        f"{100 * SENSOR_CALIBRATION:g},{100 * FORCE_CALIBRATION:g}: a datasheet's or a year-old certificate's "
        f"sensitivity; one figure for both; 0 for a calibrated chain): {role}",
    )


def add_instrumentation_arguments(parser: argparse.ArgumentParser) -> None:
    """What the instrumentation put on the body: the accelerometers' housings and the force gauges' mass."""
    add_sensor_mass_argument(
        parser,
        "KG [NODE=KG ...]",
        "mass of each accelerometer housing, kg (a triaxial counts once), then NODE=KG for a point whose "
        "housing differs (node labels as in the file, e.g. 0.004 1=0.025): the FRFs weigh the body with them on; "
        "the properties reported are the bare body's (default 0)",
    )
    parser.add_argument(
        "--exciter-mass",
        type=checked(parse_exciter_mass),
        default=0.0,
        metavar="KG",
        help="structure-side mass of the force gauge at each drive point (a shaker test; 0 for a hammer), kg: "
        "each column is fitted on the body plus it at its drive point, the properties reported are without "
        "(default 0)",
    )
