"""Dataset 58 (a function at nodal DOF) and its 1858 qualifiers, formatted as Addendum B lays them out: the
records :func:`massline.uff.writer.write_uff` writes after pyuff's geometry datasets.

Dataset 58 is formatted here, not by pyuff: pyuff's 58b header states 8 bytes per point for complex data (16 are
written), it stores an uneven abscissa of 58b in double precision where the format and real exporters use single,
and it rereads the whole file after every record. Ascii 58 values are E20.12 (13 digits), 58b values IEEE doubles
(exact); the abscissa minimum and increment are E13.5 in both.
"""

from __future__ import annotations

import numpy as np

from massline.uff.units import Characteristic

ABSCISSA = Characteristic(18, (0, 0, 0), "Frequency", "Hz")
SILENT = Characteristic(0, (0, 0, 0), "NONE", "NONE")


def ascii_line(text: str) -> str:
    """One ascii line of at most 80 characters ('NONE' when empty), as UFF id lines need."""
    line = " ".join(text.split()).encode("ascii", "replace").decode()[:80]
    return line or "NONE"


def _even_step(frequencies: np.ndarray) -> float | None:
    """Increment (Hz) of an evenly spaced axis, None for an uneven one (or a single line)."""
    steps = np.diff(frequencies)
    if len(steps) == 0 or not np.allclose(steps, steps[0], rtol=1e-9, atol=0.0):
        return None
    return float((frequencies[-1] - frequencies[0]) / len(steps))


def _characteristics(c: Characteristic) -> str:
    """Records 8-11: specific data type, length/force/temperature exponents, axis label and unit label."""
    (a, b, t), label, unit = c.exponents, c.axis_label, c.unit_label
    return f"{c.data_type:10d}{a:5d}{b:5d}{t:5d} {label:<20.20s} {unit:<20.20s}\n"


def ascii_values(x: np.ndarray, parts: list[np.ndarray], even: bool) -> bytes:
    """Record 12 in ascii: 4E20.12 (even), E13.5,2E20.12 (uneven complex), 2(E13.5,E20.12) (uneven real)."""
    columns = parts if even else [x, *parts]
    formats = ["%20.12E"] * len(parts) if even else ["%13.5E"] + ["%20.12E"] * len(parts)
    fields = [form % value for row in zip(*columns) for form, value in zip(formats, row)]
    per_line = 3 if len(columns) == 3 else 4
    return "".join("".join(fields[i : i + per_line]) + "\n" for i in range(0, len(fields), per_line)).encode()


def binary_values(x: np.ndarray, parts: list[np.ndarray], even: bool) -> bytes:
    """Record 12 in binary, little-endian: ordinates as doubles, an uneven abscissa as singles before each point."""
    fields = ([] if even else [("x", "<f4")]) + [(f"y{i}", "<f8") for i in range(len(parts))]
    packed = np.empty(len(parts[0]), dtype=fields)
    for (name, _), column in zip(fields, ([] if even else [x]) + parts):
        packed[name] = column
    return packed.tobytes()


def dataset_58(
    number: int,
    kind: int,
    ids: list[str],
    response: tuple[int, int],
    reference: tuple[int, int],
    frequencies: np.ndarray,
    values: np.ndarray,
    ordinate: tuple[Characteristic, Characteristic],
    binary: bool,
) -> bytes:
    """One function at nodal DOF, with the record layout of Addendum B (complex or real, double precision).

    ``ordinate`` holds records 9 and 10 (numerator and denominator characteristics).
    """
    step = _even_step(frequencies)
    even = step is not None
    minimum, increment = (frequencies[0], step) if even else (0.0, 0.0)
    parts = [values.real, values.imag] if np.iscomplexobj(values) else [values]
    body = (binary_values if binary else ascii_values)(frequencies, parts, even)
    opening = f"{58:6d}b{1:6d}{2:6d}{11:12d}{len(body):12d}{0:6d}{0:6d}{0:12d}{0:12d}\n" if binary else f"{58:6d}\n"
    header = "".join(
        [
            f"{-1:6d}\n",
            opening,
            *(f"{ascii_line(line):<80s}\n" for line in ids),
            f"{kind:5d}{number:10d}{1:5d}{0:10d} {'NONE':<10s}{response[0]:10d}{response[1]:4d}"
            f" {'NONE':<10s}{reference[0]:10d}{reference[1]:4d}\n",
            f"{6 if len(parts) == 2 else 4:10d}{len(frequencies):10d}{int(even):10d}"
            f"{minimum:13.5E}{increment:13.5E}{0.0:13.5E}\n",
            _characteristics(ABSCISSA),
            *map(_characteristics, ordinate),
            _characteristics(SILENT),
        ]
    )
    return header.encode("ascii") + body + f"{-1:6d}\n".encode()


def qualifiers_1858(number: int, window: int) -> bytes:
    """Dataset 1858, the qualifiers of the 58 record that follows: its set record ``number`` and ``window``
    type; everything else unknown (0)."""
    zeros = f"{0.0:15.7E}" * 5 + "\n"
    records = [f"{number:12d}" + f"{0:12d}" * 5 + "\n", f"{0:6d}{window:6d}" + f"{0:6d}" * 10 + "\n"]
    records += [zeros] * 3 + [f"{'NONE':<4s}  {'NONE':<4s}\n", f"{'NONE':<80s}\n"]
    return f"{-1:6d}\n{1858:6d}\n".encode() + "".join(records).encode() + f"{-1:6d}\n".encode()
