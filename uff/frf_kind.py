"""Which FRF a Universal File record holds — accelerance, mobility or receptance — and its factor to SI.

Exporters fill the fields that say so unreliably (``fixtures/uff/SOURCES.md``: type fields 0, 1 or wrong, unit
labels as the only hint, labels that contradict each other), so three rules are asked in turn:

1. ``"type field"``: the ordinate numerator's specific data type (8 displacement, 11 velocity, 12 acceleration)
   over a force (13, 9) or unknown (0, 1) denominator;
2. ``"unit label"``: the unit label ("m/s^2", "g", "(m/s)/N", "(1/N)*(m/s²)", over a denominator label "N",
   "lbf", ...) and the words of the axis label ("Accelerance", "Mobility", "Receptance", "Acceleration", ...);
3. ``"physics"``: the slope of log|H| against log f over the record, each decade weighted alike. Above its
   suspension modes a free body's accelerance is flat (slope 0), its mobility falls as 1/f (−1), its
   receptance as 1/f² (−2); the nearest slope decides.

The type field decides unless the labels name another kind; the labels decide when the type field is silent and
they agree among themselves; physics decides when both are silent or they contradict each other.

The scale to SI comes from the unit labels where they name units (g = 9.80665 m/s², lbf = 4.4482216152605 N,
kgf = 9.80665 N, in = 0.0254 m, mm = 0.001 m), else from dataset 164, whose factors are file units per SI unit (a
file in mm has length factor 1000): an FRF (length over force) in file units is multiplied by force / length.
Standard gravity is spelled as the exporters spell it: "g", "G", "gn", and ME'scope's "Gs" and "G's" ("Gs/N").
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError
from massline.uff.units import INCH, LBF, G

KINDS = ("accelerance", "mobility", "receptance")  # index: time derivatives from the stored FRF to accelerance
MOTION_TYPES = {12: 0, 11: 1, 8: 2}  # ordinate numerator specific data type → index in KINDS
FORCE_TYPES = (0, 1, 9, 13)  # denominator types of a force FRF: unknown, general, reaction force, excitation force
SILENT_LABELS = ("", "none", "1", "-", "?", "unknown")

LENGTH, TIME, FORCE = (1, 0, 0), (0, 1, 0), (0, 0, 1)
UNIT_SYMBOLS = {  # SI factor and exponents of (length, time, force)
    "m": (1.0, LENGTH),
    "mm": (1e-3, LENGTH),
    "cm": (1e-2, LENGTH),
    "um": (1e-6, LENGTH),
    "µm": (1e-6, LENGTH),
    "μm": (1e-6, LENGTH),
    "in": (INCH, LENGTH),
    "inch": (INCH, LENGTH),
    "ft": (0.3048, LENGTH),
    "s": (1.0, TIME),
    "sec": (1.0, TIME),
    "g": (G, (1, -2, 0)),
    "gn": (G, (1, -2, 0)),  # g_n, standard gravity
    "gs": (G, (1, -2, 0)),  # ME'scope's accelerance "Gs/N"
    "g's": (G, (1, -2, 0)),
    "n": (1.0, FORCE),
    "kn": (1e3, FORCE),
    "mn": (1e-3, FORCE),
    "lbf": (LBF, FORCE),
    "lb": (LBF, FORCE),
    "kgf": (G, FORCE),
}
KIND_WORDS = {"accel": 0, "inertance": 0, "mobil": 1, "veloc": 1, "recept": 2, "complian": 2, "displac": 2}
TOKEN = re.compile(r"[a-zµμ']+|-?\d+(?:\.\d+)?|[*/^()]")  # a symbol may hold an apostrophe: "g's"


MAX_ACCELERANCE = 1e20  # (m/s²)/N: a milligram body's resonance with Q = 10⁴ is 1e10


@dataclass(frozen=True)
class Ordinate:
    """What a dataset-58 record says about its ordinate (records 9 and 10).

    Attributes
    ----------
    numerator_type, denominator_type : int
        Specific data types (0 unknown, 1 general, 8 displacement, 11 velocity, 12 acceleration, 13 force, ...).
    axis_label, unit_label : str
        The numerator's axis label and unit label.
    denominator_unit_label : str
        The denominator's unit label.
    """

    numerator_type: int
    denominator_type: int
    axis_label: str
    unit_label: str
    denominator_unit_label: str


@dataclass(frozen=True)
class Decision:
    """The kind of one FRF and its factor to SI.

    Attributes
    ----------
    kind : str
        "accelerance", "mobility" or "receptance": what the record stores.
    rule : str
        "type field", "unit label" or "physics": the rule that decided.
    scale : float
        Factor from the record's units to SI: (m/s²)/N, (m/s)/N or m/N.
    warnings : tuple of str
        What was odd and tolerated (contradicting fields, unknown labels).
    """

    kind: str
    rule: str
    scale: float
    warnings: tuple[str, ...] = ()


def units(label: str) -> tuple[float, tuple[int, int, int]] | None:
    """SI factor and (length, time, force) exponents of a unit label; None for one not understood.

    A silent label ("NONE", "", "1") is dimensionless: (1.0, (0, 0, 0)). Products, quotients, brackets and
    powers are understood: "(m/s^2)/N", "(1/N)*(m/s²)", "m s^-2 N^-1", "g/lbf".
    """
    text = label.strip().lower().replace("²", "^2").replace("³", "^3").replace("**", "^").replace("·", "*")
    if text in SILENT_LABELS:
        return 1.0, (0, 0, 0)
    text = re.sub(r"(?<=[a-z])(\d)", r"^\1", text)
    tokens = TOKEN.findall(text)
    if "".join(tokens) != re.sub(r"\s", "", text):
        return None
    try:
        value, end = _product(tokens, 0)
    except (KeyError, IndexError, ValueError):
        return None
    return value if end == len(tokens) else None


def _product(tokens: list[str], i: int):
    """Factors joined by '*', '/' or juxtaposition, up to a ')' or the end; returns the value and next index."""
    (factor, dims), i = _power(tokens, i)
    while i < len(tokens) and tokens[i] != ")":
        sign = -1 if tokens[i] == "/" else 1
        i += tokens[i] in "*/"
        (f, d), i = _power(tokens, i)
        factor, dims = factor * f**sign, tuple(a + sign * b for a, b in zip(dims, d))
    return (factor, dims), i


def _power(tokens: list[str], i: int):
    """A symbol, number or bracket, raised to an optional '^ n'."""
    if tokens[i] == "(":
        base, i = _product(tokens, i + 1)
        if tokens[i] != ")":
            raise ValueError("unbalanced bracket")
        i += 1
    elif tokens[i][-1].isdigit():
        base, i = (float(tokens[i]), (0, 0, 0)), i + 1
    else:
        base, i = UNIT_SYMBOLS[tokens[i]], i + 1
    if i < len(tokens) and tokens[i] == "^":
        n = int(tokens[i + 1])
        return (base[0] ** n, tuple(n * e for e in base[1])), i + 2
    return base, i


def _motion_kind(dims) -> int | None:
    """Index in KINDS of a motion unit (length per time^k) or an FRF unit (that per force)."""
    length, time, force = dims
    return time + 2 if length == 1 and force in (0, -1) and time in (-2, -1, 0) else None


def label_kinds(ordinate: Ordinate) -> set[int]:
    """Kinds (indices in KINDS) that the unit label and the axis label's words name."""
    parsed = units(ordinate.unit_label)
    kinds = {_motion_kind(parsed[1])} if parsed else set()
    words = ordinate.axis_label.lower()
    kinds |= {kind for word, kind in KIND_WORDS.items() if word in words}
    return kinds - {None}


def scale_to_si(ordinate: Ordinate, length: float = 1.0, force: float = 1.0) -> float:
    """Factor from the record's FRF units to SI: from the unit labels, else dataset 164's factors.

    ``length`` and ``force`` are dataset 164's factors (file units per metre, per newton).
    """
    top, bottom = units(ordinate.unit_label), units(ordinate.denominator_unit_label)
    if top and top[1][2] == -1:
        return top[0]
    numerator = top[0] if top and top[1][0] == 1 else 1.0 / length
    denominator = bottom[0] if bottom and bottom[1] == FORCE else 1.0 / force
    return numerator / denominator


def log_slope(frequencies: np.ndarray, values: np.ndarray) -> float | None:
    """Slope of log|H| against log f (f > 0, H ≠ 0), each point weighted by its share of log f; None if < 3 points."""
    keep = (frequencies > 0) & np.isfinite(values) & (np.abs(values) > 0)
    if keep.sum() < 3:
        return None
    x, y = np.log(frequencies[keep]), np.log(np.abs(values[keep]))
    return float(np.polyfit(x, y, 1, w=np.sqrt(np.abs(np.gradient(x))))[0])


def _unknown_labels(ordinate: Ordinate, name: str) -> tuple[str, ...]:
    labels = (ordinate.unit_label, ordinate.denominator_unit_label)
    return tuple(f"{name}: unit label {label!r} not understood" for label in labels if units(label) is None)


def decide(
    ordinate: Ordinate, frequencies: np.ndarray, values: np.ndarray, length=1.0, force=1.0, name="FRF"
) -> Decision:
    """Kind of an FRF record by type field, then unit label, then physics; and its factor to SI.

    Parameters
    ----------
    ordinate : Ordinate
        The record's type fields and labels.
    frequencies : (n,) array
        Hz.
    values : (n,) array
        The record's values, in file units.
    length, force : float
        Dataset 164's factors (file units per metre, per newton); 1 when the file has none.
    name : str
        How warnings name the record.
    """
    notes = _unknown_labels(ordinate, name)
    by_type = MOTION_TYPES.get(ordinate.numerator_type) if ordinate.denominator_type in FORCE_TYPES else None
    said = label_kinds(ordinate)
    by_label = next(iter(said)) if len(said) == 1 else None
    scale = scale_to_si(ordinate, length, force)
    if by_type is not None and by_label in (None, by_type):
        if len(said) > 1:
            kinds = ", ".join(KINDS[k] for k in sorted(said))
            notes += (f"{name}: its labels name different kinds ({kinds}): its type field decides",)
        return Decision(KINDS[by_type], "type field", scale, notes)
    if by_type is None and by_label is not None:
        return Decision(KINDS[by_label], "unit label", scale, notes)
    slope = log_slope(frequencies, values)
    kind = 0 if slope is None else int(np.clip(np.round(-slope), 0, 2))
    if by_type is not None:
        why = f"its type field says {KINDS[by_type]}, its labels {KINDS[by_label]}"
    else:
        why = "its labels contradict each other" if said else "neither its type field nor its labels name its kind"
    found = "too few points for a slope" if slope is None else f"log|H| has slope {slope:.2f} against log f"
    return Decision(KINDS[kind], "physics", scale, notes + (f"{name}: {why}; {found}: read as {KINDS[kind]}",))


def to_accelerance(kind: str, frequencies: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Accelerance from an FRF of ``kind``: mobility × iω, receptance × (iω)² = −ω² (ω = 2πf, f in Hz)."""
    return np.asarray(values, dtype=complex) * (2j * np.pi * np.asarray(frequencies)) ** KINDS.index(kind)


def check_accelerance(values: np.ndarray, where: str) -> None:
    """Refuse an FRF with NaN or infinite values (in the file, or beyond a double once in SI), or values no
    accelerance reaches (a damaged exponent)."""
    for bad, what in (
        (~np.isfinite(values), "NaN or infinite values"),
        (np.abs(values) > MAX_ACCELERANCE, f"values beyond any body's accelerance ({MAX_ACCELERANCE:.0e} (m/s²)/N)"),
    ):
        if bad.any():
            raise MasslineError(
                f"{where} has {what} at {bad.sum()} of {len(values)} frequencies: export it again or leave it out"
            )
