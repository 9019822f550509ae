"""What every exported file says about itself, in comment lines: what was measured, with what ±, or that the
values were given (a CAD body's, no 1-σ), in which frame and units, by which version of massline, and how the
format's inertia entries are signed.

Plain ASCII (solver decks are read by Fortran-era parsers): '+/-', '1-sigma', 'int(xy dm)'.
"""

from __future__ import annotations

import textwrap

import numpy as np

from massline.core import __version__
from massline.core.numbers import value_with_sigma
from massline.export.units import Units

WIDTH = 72  # comment text per line: a card deck's 80 columns less the comment marker
AXES = "xyz"
MEASURED_FRAME = "the recording's frame O xyz (the file's)"
GIVEN_FRAME = "the frame O xyz the values were given in"
TENSOR_SIGN = "inertia tensor about the CoG, J = int((r.r) I - r r^T) dm: J_xy = -int(xy dm)"


def ascii_text(text: str) -> str:
    """``text`` with the typographic signs massline prints ('−', '±', '·', 'σ', '–') spelled in ASCII."""
    for typographic, plain in (("−", "-"), ("±", "+/-"), ("·", " "), ("σ", "sigma"), ("–", "-"), ("²", "^2")):
        text = text.replace(typographic, plain)
    return text.encode("ascii", "replace").decode()


def measured(value: float, sigma: float | None, unit: str, given: bool = False) -> str:
    """'0.34560 +/- 0.00012 kg', the value to its 1-sigma's last digit; 'unobserved' for NaN; a ``given`` value
    (no 1-sigma at all) in full."""
    if np.isnan(value):
        return "unobserved"
    if given:
        return ascii_text(f"{real(value)} {unit}")
    shown, spread = value_with_sigma(value, None if sigma is None or np.isnan(sigma) else sigma)
    return ascii_text(f"{shown} +/- {spread} {unit}" if spread else f"{shown} {unit} (1-sigma not given)")


def measured_lines(body, units: Units) -> list[str]:
    """Mass, CoG and the six inertia entries (tensor sign), each with its 1-sigma, in ``units``."""
    std, given = body.std or {}, body.std is None
    mass_sd = std.get("mass")
    cog_sd = np.asarray(std.get("cog", np.full(3, np.nan)), dtype=float)
    J_sd = np.asarray(std.get("inertia_cog", np.full((3, 3), np.nan)), dtype=float)
    cog, J = units.lengths(body.cog), units.inertias(body.inertia)
    mass = measured(units.masses(body.mass), None if mass_sd is None else units.masses(mass_sd), units.mass, given)
    lines = [f"mass = {mass}"]
    lines += [
        f"CoG {a} = {measured(cog[k], units.lengths(cog_sd[k]), units.length, given)}" for k, a in enumerate(AXES)
    ]
    lines += [
        f"J_{AXES[i]}{AXES[j]} = {measured(J[i, j], units.inertias(J_sd[i, j]), units.inertia, given)}"
        for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))
    ]
    return lines


def header_lines(body, units: Units, convention: str) -> list[str]:
    """The comment block, one entry a line (wrapped to ``WIDTH``), for a format whose inertia entries follow
    ``convention`` (a sentence citing the format's manual)."""
    parts = [
        f"massline {__version__} export: {body.note or 'a body given to massline (not measured)'}",
        f"frame: {GIVEN_FRAME if body.std is None else MEASURED_FRAME}; the CoG in it, the inertia about the CoG "
        "along its axes",
        f"units: length {units.length}, mass {units.mass}, inertia {units.inertia} (time s, force N)",
        (f"given, not measured (no 1-sigma; {TENSOR_SIGN}):" if body.std is None
         else f"measured (value +/- 1-sigma; {TENSOR_SIGN}):"),  # fmt: skip
        *(f"  {line}" for line in measured_lines(body, units)),
        f"this format: {convention}",
        *(f"warning: {w}" for w in body.warnings),
    ]
    lines = []
    for part in parts:
        indent = "  " if part.startswith("  ") else ""
        lines += textwrap.wrap(ascii_text(part), WIDTH, subsequent_indent=indent + "  ") or [""]
    return lines


def commented(lines: list[str], marker: str) -> str:
    """Each line after ``marker`` (e.g. '$ ', '** ', '! ', '# '), one text ending in a newline."""
    return "".join(f"{marker}{line}".rstrip() + "\n" for line in lines)


def real(value: float) -> str:
    """A number as a text format writes it: 12 significant digits (5e−13 relative), 'e' exponent."""
    return f"{float(value):.12g}"


def xml_comment(lines: list[str], indent: str = "") -> str:
    """The lines as one XML comment block ('--' is not allowed inside one: spelled '- -')."""
    body = "".join(f"{indent}     {line.replace('--', '- -')}".rstrip() + "\n" for line in lines)
    return f"{indent}<!--\n{body}{indent}-->\n"
