"""Every unit-label spelling and axis word the UFF reader accepts, each read at the SI factor its unit's definition
gives (written here, not read from the reader's tables): a symbol added to the reader without its test fails."""

import numpy as np
import pytest
from test_uff_reader import EXCITERS, FREQUENCIES, GRID, KIND_CASES, SENSORS, assert_close, function, write

from massline.uff.frf_kind import KIND_WORDS, UNIT_SYMBOLS
from massline.uff.reader import read_uff

# every spelling the reader accepts, at the SI factor its unit's definition gives (written here, not read from it)
G_N, LBF_N = 9.80665, 4.4482216152605  # standard gravity, m/s²; the pound-force, N
SYMBOLS = {  # symbol (lower case, as UNIT_SYMBOLS keys it): a label holding it over a denominator, and its factor
    **{u: (f"{u}/s^2", "N", f) for u, f in [("m", 1.0), ("mm", 1e-3), ("cm", 1e-2), ("ft", 0.3048)]},
    **{u: (f"{u}/s^2", "N", 1e-6) for u in ("um", "µm", "μm")},
    **{u: (f"{u}/s^2", "N", 0.0254) for u in ("in", "inch")},
    **{u: (f"m/{u}^2", "N", 1.0) for u in ("s", "sec")},
    **{u: (u.upper(), "N", G_N) for u in ("g", "gn", "gs", "g's")},
    **{u: ("m/s^2", u.upper(), 1 / f) for u, f in [("n", 1.0), ("kn", 1e3), ("mn", 1e-3), ("kgf", G_N)]},
    **{u: ("m/s^2", u.upper(), 1 / LBF_N) for u in ("lbf", "lb")},
}
EXPORTED = {  # whole labels as exporters write them: (numerator, denominator) and the factor to (m/s²)/N
    "Gs/N (ME'scope)": ("Gs/N", "NONE", G_N),
    "Gs/N over N": ("Gs/N", "N", G_N),
    "Gs over N": ("Gs", "N", G_N),
    "g/N": ("g", "N", G_N),
    "g/lbf": ("g", "lbf", G_N / LBF_N),
    "m/s^2/N": ("m/s^2", "N", 1.0),
    "m/s²/N": ("m/s²", "N", 1.0),
    "(m/s^2)/lbf": ("m/s^2", "lbf", 1 / LBF_N),
    "G's/N": ("G's", "N", G_N),
    "g's/N": ("g's", "N", G_N),
    "gn/N": ("gn", "N", G_N),
    "g/kgf": ("g", "kgf", 1.0),
    "(m/s²)/kgf": ("(m/s²)/kgf", "NONE", 1 / G_N),
    "in/s²/lbf": ("in/s^2", "lbf", 0.0254 / LBF_N),
}


def test_every_unit_symbol_is_tested():
    assert set(SYMBOLS) == set(UNIT_SYMBOLS)


@pytest.mark.parametrize("labels", list(SYMBOLS.values()) + list(EXPORTED.values()), ids=[*SYMBOLS, *EXPORTED])
def test_each_unit_spelling_reads_at_its_si_factor(tmp_path, labels):
    """An accelerance record labelled ``labels`` reads back as its values times the unit's factor to (m/s²)/N."""
    numerator, denominator, factor = labels
    stored = GRID[0, 0]
    path = write(tmp_path / "unit.uff", [function(SENSORS[0], EXCITERS[0], stored, labels=(numerator, denominator))])
    [frf] = read_uff(path).frfs
    assert frf.kind == "accelerance" and frf.rule == "type field"
    assert_close(frf.accelerance, stored * factor, 1e-9)


AXIS_WORDS = {  # an axis label as exporters write it: the kind it names (KIND_WORDS' word in it)
    "Acceleration": "accelerance",
    "Inertance": "accelerance",
    "Mobility": "mobility",
    "Velocity": "mobility",
    "Receptance": "receptance",
    "Compliance": "receptance",
    "Displacement": "receptance",
}


def test_every_kind_word_is_tested():
    assert {word for word in KIND_WORDS for label in AXIS_WORDS if word in label.lower()} == set(KIND_WORDS)


@pytest.mark.parametrize("axis", list(AXIS_WORDS))
def test_each_axis_word_names_its_kind(tmp_path, axis):
    """Type fields and unit labels silent: the axis label's word decides, and the record reads as accelerance."""
    kind = AXIS_WORDS[axis]
    stored = GRID[0, 0] / (2j * np.pi * FREQUENCIES) ** KIND_CASES[kind][0]
    record = function(SENSORS[0], EXCITERS[0], stored, types=(1, 0), ordinate_axis_lab=axis)
    [frf] = read_uff(write(tmp_path / "kind.uff", [record])).frfs
    assert (frf.kind, frf.rule) == (kind, "unit label")
    assert_close(frf.accelerance, GRID[0, 0], 1e-9)
