"""The datasets of a Universal File (UFF/UNV): split at their '    -1' delimiters and parsed.

Parsed here: 151 header, 164 units, 15 and 2411 nodes, 18 and 2420 coordinate systems, 58 and 58b functions
(ascii or binary, 4- or 8-byte, real or complex, even or uneven abscissa) and the window type of 1858 (the 58
qualifiers: 4 exponential, 5 impact, 6 impact and exponential); other datasets are listed, not parsed.

The file is split and parsed here, not by pyuff 2.5, whose dataset-58 reader misreads what real exporters write:
it reads an uneven 58b abscissa in single precision (the format's, and real files') as doubles, keeps padding
beyond num_pts, and drops a truncated last record without a word; pyuff's own 58b writer states half the byte
count of complex data, and an uneven abscissa in doubles: both are read here.

Values stay in file units and local systems; `uff` places them in the global frame and in SI.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from massline.core.errors import MasslineError
from massline.uff.frf_kind import Ordinate
from massline.uff.recording import Channel

DELIMITER = re.compile(rb"^    -1[ \t\r]*$", re.M)
CLOSING = re.compile(rb"(?:\r?\n)?    -1[ \t\r]*(?:\n|\Z)")
TRAILING = re.compile(rb"\s*\Z")
NAMED_CHANNEL = re.compile(r"(\d+)[^A-Za-z\d]*([+-]?)([XYZ])([+-]?)$")
FUNCTION_NAMES = ("general", "time response", "auto spectrum", "cross spectrum", "FRF", "transmissibility")
FUNCTION_NAMES += ("coherence", "auto correlation", "cross correlation", "PSD", "ESD", "PDF", "spectrum")


@dataclass(frozen=True, eq=False)
class RawDataset:
    """One dataset: its number, the line of its opening delimiter, its text after the identifier line
    (up to the data of a 58b), a 58b's byte order and data, and its bytes in the file (``span``: from its
    opening delimiter to after its closing one)."""

    number: int
    line: int
    text: str
    binary: tuple[str, bytes] | None = None
    span: tuple[int, int] = (0, 0)

    @cached_property
    def lines(self) -> list[str]:
        return self.text.splitlines()

    def head(self, count: int) -> tuple[list[str], str]:
        """The first ``count`` lines, and the text after them: an ascii 58's data, split into numbers without
        first being split into lines."""
        parts = self.text.split("\n", count)
        rest = parts.pop() if len(parts) > count else ""
        return [part.rstrip("\r") for part in parts], rest


@dataclass(frozen=True, eq=False)
class Function:
    """One dataset-58 record, in file units."""

    line: int
    type: int
    response: Channel
    reference: Channel
    ordinate: Ordinate
    frequencies: np.ndarray
    values: np.ndarray


def _truncated(name: str, block_number: int, line: int) -> MasslineError:
    return MasslineError(
        f"file {name} is truncated: its dataset {block_number} starting at line {line} has no end marker "
        "('    -1'); the export or copy was cut short: export the file again"
    )


def _line_end(data: bytes, start: int) -> int:
    end = data.find(b"\n", start)
    return len(data) if end < 0 else end


def _binary_lengths(n_bytes: int, record_7: str) -> list[int]:
    """Possible lengths of a 58b's data: the header's byte count, then num_pts × the point size (an uneven
    abscissa in 4 bytes as the format says, or 8 as pyuff writes it)."""
    kind, num_pts, spacing = (int(v) for v in record_7.split()[:3])
    value = (4 if kind in (2, 5) else 8) * (2 if kind in (5, 6) else 1)
    return [n_bytes] + [num_pts * (value + a) for a in ((0,) if spacing == 1 else (4, 8))]


def _binary_block(data: bytes, first: int, ident: str, line: int, name: str) -> tuple[RawDataset, int]:
    """A 58b: 11 ascii header lines, then raw IEEE values of the first possible length that ends at a closing
    delimiter."""
    order, fp_format, n_lines, n_bytes = (int(v) for v in ident[7:].split()[:4])
    end = _line_end(data, first)
    for _ in range(n_lines):  # an absurd count stops at the end of the data
        end = _line_end(data, end + 1)
        if end >= len(data):
            break
    if end >= len(data):
        raise _truncated(name, 58, line)
    text = data[_line_end(data, first) + 1 : end].decode("latin-1")
    lines = text.splitlines()
    if fp_format != 2:
        raise MasslineError(
            f"file {name}: the 58b record at line {line} holds floating-point format {fp_format}, not IEEE 754 "
            "(2): export the FRFs as ascii 58 or IEEE binary"
        )
    lengths = _binary_lengths(n_bytes, lines[6])
    length = next((n for n in lengths if CLOSING.match(data, end + 1 + n)), None)
    if length is None and len(data) < end + 1 + max(lengths) + 6:
        raise _truncated(name, 58, line)
    if length is None:
        raise MasslineError(
            f"file {name}: the binary data of the 58b record at line {line} do not end where its header says "
            f"({n_bytes} bytes): the file is damaged; export it again"
        )
    block = RawDataset(58, line, text, ("<" if order == 1 else ">", data[end + 1 : end + 1 + length]))
    return block, CLOSING.match(data, end + 1 + length).end()


def _delimiter(data: bytes, start: int) -> re.Match | None:
    """The first '    -1' delimiter line at or after ``start``: its candidates found by bytes.find, several
    times faster than a regex scanning every line of a large file."""
    at = data.find(b"    -1", start)
    while at >= 0:
        if (found := DELIMITER.match(data, at)) is not None:
            return found
        at = data.find(b"    -1", at + 1)
    return None


def _block(data: bytes, first: int, line: int, name: str) -> tuple[RawDataset, int]:
    """The dataset whose identifier line starts at ``first``, and the offset after its closing delimiter."""
    ident = data[first : _line_end(data, first)].decode("latin-1")
    try:
        if ident[6:7].lower() == "b":
            return _binary_block(data, first, ident, line, name)
        number = int(ident[:6])
    except MasslineError:
        raise
    except (ValueError, IndexError):
        raise MasslineError(
            f"file {name}: the dataset at line {line} has an unreadable header ({ident.strip()[:20]!r}): "
            "the file is damaged or not in the UFF format; export it again"
        ) from None
    closing = _delimiter(data, first)
    if closing is None:
        raise _truncated(name, number, line)
    text = data[_line_end(data, first) + 1 : closing.start()].decode("latin-1")
    return RawDataset(number, line, text), closing.end()


def split(data: bytes, name: str) -> list[RawDataset]:
    """The datasets of a file, each between two '    -1' lines (a 58b's binary data skipped by its length)."""
    blocks, position, line, counted = [], 0, 1, 0
    while (opening := _delimiter(data, position)) is not None and not TRAILING.match(data, opening.end()):
        line, counted = line + data.count(b"\n", counted, opening.start()), opening.start()
        block, position = _block(data, opening.end() + 1, line, name)
        blocks.append(replace(block, span=(opening.start(), position)))
    return blocks


def _numbers(text: str) -> np.ndarray:
    """Fortran numbers separated by blanks (E or D exponents)."""
    return np.array(text.upper().replace("D", "E").split(), dtype=float)


def _finite(values: np.ndarray, what: str) -> np.ndarray:
    """``values`` if every one is finite, else a ValueError naming ``what``."""
    if not np.isfinite(values).all():
        raise ValueError(f"NaN or infinite {what}")
    return values


def _int(field: str) -> int:
    return int(field) if field.strip() else 0


def _label(field: str) -> str:
    """A label read as latin-1 (one byte per column), re-read as UTF-8 when it is."""
    try:
        return field.strip().encode("latin-1").decode("utf-8")
    except UnicodeDecodeError:
        return field.strip()


def _units_164(block: RawDataset) -> tuple[float, float]:
    """Length and force factors: file units per metre, per newton."""
    factors = _finite(_numbers(" ".join(block.lines[1:]))[:2], "unit factors")
    if not (len(factors) == 2 and np.all(factors > 0)):
        raise ValueError(f"length and force factors {factors} must be positive")
    return float(factors[0]), float(factors[1])


def _header_151(block: RawDataset) -> str:
    return " ".join(t for t in (block.lines[0].strip(), block.lines[1].strip()) if t not in ("", "NONE"))


def _nodes(block: RawDataset) -> np.ndarray:
    """Rows (label, definition system, displacement system, colour, x, y, z) of dataset 15 or 2411."""
    values = _finite(_numbers(" ".join(block.lines)), "node label or coordinate")
    if values.size % 7:
        raise ValueError(f"{values.size} numbers, not 7 per node")
    return values.reshape(-1, 7)


def _frame_18(origin, x_point, xz_point) -> np.ndarray:
    """Axes (columns) of a system from its origin, a point on +x and a point in the +xz plane."""
    x = x_point - origin
    if not np.linalg.norm(x) > 0:
        raise ValueError("its point on the x axis is its origin")
    z = xz_point - origin - ((xz_point - origin) @ x) / (x @ x) * x
    if np.linalg.norm(z) < 1e-9 * np.linalg.norm(x):
        raise ValueError("its point in the xz plane lies on its x axis")
    x, z = x / np.linalg.norm(x), z / np.linalg.norm(z)
    return np.column_stack([x, np.cross(z, x), z])


def _records(lines: list[str], head: int, count: int):
    """Per system: the numbers of its first line, its name line, then ``count`` numbers over the next lines."""
    lines, i = list(lines), head
    while lines and not lines[-1].strip():
        lines.pop()
    while i < len(lines):
        first, values, i = lines[i].split(), [], i + 2
        while len(values) < count:
            values, i = [*values, *_numbers(lines[i])], i + 1
        yield [int(v) for v in first], _finite(np.array(values[:count]), "coordinate system value")


def _systems_18(block: RawDataset) -> dict:
    """{label: (type, reference system, origin, axes)} of dataset 18, in the reference system."""
    return {
        label: (kind, reference, v[:3], _frame_18(*v.reshape(3, 3)))
        for (label, kind, reference, *_), v in _records(block.lines, 0, 9)
    }


def _systems_2420(block: RawDataset) -> dict:
    """{label: (type, 0, origin, axes)} of dataset 2420, in the global frame."""
    return {label: (kind, 0, v[9:], v[:9].reshape(3, 3).T) for (label, kind, *_), v in _records(block.lines, 2, 12)}


def _channel(name: str, node: str, code: str, where: str, role: str) -> tuple[Channel, list[str]]:
    """(node, direction code) of a record; from the entity name (e.g. '.1.Z-', 'Point12:+X') when both are 0."""
    channel, match = Channel(_int(node), _int(code)), NAMED_CHANNEL.search(name.strip())
    if channel != (0, 0) or match is None:
        return channel, []
    number, before, axis, after = match.groups()
    channel = Channel(int(number), (-1 if "-" in before + after else 1) * ("XYZ".index(axis) + 1))
    return channel, [f"{where}: {role} {channel} read from its name {name.strip()!r}"]


def _binary_rows(order: str, payload: bytes, kind: int, even: bool, num_pts: int) -> np.ndarray:
    """58b values as rows (abscissa if uneven, ordinate part(s)); an uneven abscissa in 4 bytes, or 8 as pyuff
    writes it."""
    size, parts = (4 if kind in (2, 5) else 8), (2 if kind in (5, 6) else 1)
    abscissa = 0 if even else (8 if len(payload) == num_pts * (8 + parts * size) else 4)
    fields = ([("x", f"{order}f{abscissa}")] if abscissa else []) + [("y", f"{order}f{size}", (parts,))]
    dtype = np.dtype(fields)
    table = np.frombuffer(payload[: len(payload) // dtype.itemsize * dtype.itemsize], dtype=dtype)
    return np.column_stack(([table["x"]] if abscissa else []) + [table["y"].reshape(len(table), parts)]).astype(float)


def _kept_points(rows: np.ndarray, num_pts: int, where: str) -> tuple[np.ndarray, list[str]]:
    """The points to read: num_pts when the rest is zero padding, else all of them."""
    if len(rows) > num_pts and not rows[num_pts:].any():
        return rows[:num_pts], [f"{where}: {len(rows) - num_pts} points of zero padding after num_pts ignored"]
    if len(rows) != num_pts:
        return rows, [f"{where}: num_pts says {num_pts} but the record holds {len(rows)} points; all read"]
    return rows, []


def _function(block: RawDataset) -> tuple[Function, list[str]]:
    """A dataset-58 record (records 1-11, then the data) and what was odd in it."""
    lines, data = block.head(11)
    where = f"dataset 58 at line {block.line}"
    r6, r7 = lines[5], lines[6].split()
    kind, num_pts, spacing = (int(v) for v in r7[:3])
    minimum, increment = (float(v.upper().replace("D", "E")) for v in r7[3:5])
    response, notes = _channel(r6[31:41], r6[41:51], r6[51:55], where, "response")
    reference, more = _channel(r6[56:66], r6[66:76], r6[76:80], where, "reference")
    parts, even = (2 if kind in (5, 6) else 1), spacing == 1
    if block.binary is None:
        flat, width = _numbers(data), parts + (not even)
        rows = flat[: flat.size // width * width].reshape(-1, width)
        notes += (
            [f"{where}: {flat.size % width} value(s) after the last whole point ignored"] if flat.size % width else []
        )
    else:
        rows = _binary_rows(*block.binary, kind, even, num_pts)
    rows, kept = _kept_points(rows, num_pts, where)
    frequencies = _finite(minimum + increment * np.arange(len(rows)) if even else rows[:, 0], "abscissa (frequency)")
    values = rows[:, -2] + 1j * rows[:, -1] if parts == 2 else rows[:, -1]
    numerator, denominator = lines[8], lines[9]
    ordinate = Ordinate(
        _int(numerator[:10]),
        _int(denominator[:10]),
        _label(numerator[26:46]),
        _label(numerator[47:67]),
        _label(denominator[47:67]),
    )
    function = Function(block.line, _int(r6[:5]), response, reference, ordinate, frequencies, values)
    return function, notes + more + kept


def _window_1858(block: RawDataset) -> int:
    """The window type of a dataset 1858 (record 2, field 2): 0 none or unknown, 1–3 Hanning or flattop,
    4 exponential, 5 impact (force window), 6 impact and exponential."""
    return int(block.lines[1].split()[1])


def function_name(kind: int) -> str:
    """Name of a dataset-58 function type: 'FRF', 'coherence', 'time response', ..."""
    return FUNCTION_NAMES[kind] if 0 <= kind < len(FUNCTION_NAMES) else f"function type {kind}"


PARSERS = {
    15: _nodes,
    2411: _nodes,
    18: _systems_18,
    2420: _systems_2420,
    164: _units_164,
    151: _header_151,
    58: _function,
    1858: _window_1858,
}


def parse(block: RawDataset, name: str):
    """The block's contents by its dataset's parser; None for datasets not read."""
    parser = PARSERS.get(block.number)
    if parser is None:
        return None
    try:
        with np.errstate(all="ignore"):  # a damaged file's NaN and infinities are refused by the checks, quietly
            return parser(block)
    except (ValueError, IndexError, KeyError, TypeError) as error:
        raise MasslineError(
            f"file {name}: dataset {block.number} at line {block.line} is unreadable ({error}): the file is damaged "
            "or not in the UFF format; export it again"
        ) from None
