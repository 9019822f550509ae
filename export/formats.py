"""Which format a file name asks for, whether it can hold a body, and the writing of it.

A format is named by its file's suffix (``FORMATS``). Refusals come before any work where they can
(``check_export``: the suffix, the unit system, the path), and before the file is touched otherwise
(``check_holds``: a body the format cannot hold).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from massline.core.errors import MasslineError, param
from massline.core.files import atomic_file, claim_output
from massline.export import abaqus, adams, csv_row, mjcf, nastran, sdf, urdf
from massline.export.units import SI, Units, unit_system

TRIANGLE_TOLERANCE = 1e-9  # relative: J1 + J2 ≥ J3 (1 − this), rounding of an exactly flat body


@dataclass(frozen=True)
class Format:
    """An export format: its name, its writer (``Body``, ``Units`` → text), whether it fixes metres and
    kilograms and whether it can hold a body with unobserved entries (a plate's)."""

    name: str
    write: Callable
    si_only: bool = False
    holds_unobserved: bool = False


NASTRAN = Format("Nastran bulk data (GRID + CONM2)", nastran.bulk_data)
FORMATS = {
    ".bdf": NASTRAN,
    ".dat": NASTRAN,
    ".inp": Format("Abaqus input (*MASS + *ROTARY INERTIA)", abaqus.keywords),
    ".adm": Format("Adams dataset (PART)", adams.dataset),
    ".urdf": Format("URDF <inertial>", urdf.robot, si_only=True),
    ".sdf": Format("SDFormat <inertial>", sdf.model, si_only=True),
    ".xml": Format("MuJoCo MJCF <inertial>", mjcf.model, si_only=True),
    ".csv": Format("CSV row", csv_row.table, holds_unobserved=True),
}
"""Every export format, by the suffix that names it."""


def format_of(path: str | Path) -> Format:
    """The format the suffix of ``path`` names; refused when it names none."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        known = ", ".join(FORMATS)
        raise MasslineError(f"{path}: no export format has the suffix '{suffix}'; give one of {known}")
    return FORMATS[suffix]


def check_export(path: str | Path, units: str | Units = SI, force: bool = False) -> Format:
    """Before any work: the format ``path`` names, whether it takes ``units``, and whether ``path`` may be written."""
    found, units = format_of(path), unit_system(units)
    if found.si_only and units != SI:
        raise MasslineError(
            f"{param('units', repr(units.name), cli=units.name)}: {found.name} takes metres and kilograms "
            f"({path}); write it in m-kg or export .bdf, .inp, .adm or .csv"
        )
    claim_output(path, force)
    return found


def check_observed(path: str | Path, unobserved: tuple[str, ...]) -> None:
    """Refuse a body with ``unobserved`` entries (a plate's test: z_G and J's z row and column) in a format
    that needs a whole body (every one but CSV)."""
    found = format_of(path)
    if unobserved and not found.holds_unobserved:
        raise MasslineError(
            f"{path}: the test leaves {', '.join(unobserved)} unobserved (plate data); {found.name} needs a "
            "whole body: export .csv (empty cells) or measure with lines off z"
        )


def check_holds(body, path: str | Path) -> None:
    """Refuse a body (a ``Body``) the format of ``path`` cannot hold: unobserved entries, or in a format that
    needs a whole body, an inertia no rigid body has (principal moments J1 ≤ J2 ≤ J3 need J1 > 0 and
    J1 + J2 ≥ J3), which a solver would reject or run wrong."""
    check_observed(path, body.unobserved)
    if format_of(path).holds_unobserved:
        return
    J1, J2, J3 = body.principal_moments
    if not (J1 > 0 and J1 + J2 >= J3 * (1 - TRIANGLE_TOLERANCE)):
        raise MasslineError(
            f"{path}: principal moments {J1:.4g}, {J2:.4g}, {J3:.4g} kg m^2 are no rigid body's "
            "(J1 > 0 and J1 + J2 >= J3 needed); use the weighted estimate (method best) or export .csv"
        )


def export_text(body, path: str | Path, units: str | Units = SI) -> str:
    """The text of ``body`` (a ``Body``) in the format the suffix of ``path`` names, in ``units``."""
    check_holds(body, path)
    return format_of(path).write(body, unit_system(units))


def write_export(body, path: str | Path, units: str | Units = SI, force: bool = False) -> Path:
    """Write ``body`` (a ``Body``) to ``path`` in the format its suffix names, whole or not at all."""
    check_export(path, units, force)
    text = export_text(body, path, units)
    path = Path(path)
    with atomic_file(path) as temporary:
        temporary.write_text(text, encoding="ascii")  # every writer's text is ASCII (header.ascii_text)
    return path
