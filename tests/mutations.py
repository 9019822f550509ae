"""Mutated input files for the fuzz tests: damaged UFFs and meshes, grown from real files.

Seeds are the real exporters' files in ``tests/fixtures/`` and the project's own exports (a
small virtual test written in three exporter styles, the bundled bodies as binary STL, ASCII STL,
OBJ and PLY). Each mutation takes the file's bytes and a ``random.Random`` and returns new bytes:
byte flips, truncation at a record boundary, records swapped, duplicated or emptied, type fields
and counts set to wrong or absurd values, non-ASCII text, NaN and infinities in numeric fields.
A record is a UFF dataset (between '    -1' delimiters) or a line, a binary STL facet or a text
mesh's line.
"""

from __future__ import annotations

import json
import random
import re
import struct
from pathlib import Path

from conftest import FIXTURE_MESHES, FIXTURE_UFF

DELIMITER = re.compile(rb"^    -1[ \t\r]*$", re.M)
NUMBER = re.compile(rb"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eEdD][-+]?\d+)?")
INTEGER = re.compile(rb"(?<![\d.eE+-])[-+]?\d+(?![\d.eE])")
SPECIAL = (b"NaN", b"nan", b"inf", b"-inf", b"Infinity", b"1e999", b"-1e999", b"1.#QNAN")
ABSURD = (b"0", b"-1", b"-2147483648", b"2147483647", b"4294967295", b"999999999999", b"99")
NON_ASCII = ("Ä", "µ", "°", "☃", "\x00", "\ufeff", "é", "—")
FLOATS = (float("nan"), float("inf"), -float("inf"), 3.4e38, -0.0, 1e-45)


def _lines(data: bytes) -> list[int]:
    """Offsets where each line starts (and the end of the file)."""
    return [0] + [m.end() for m in re.finditer(rb"\n", data)] + [len(data)]


def _datasets(data: bytes) -> list[tuple[int, int]]:
    """(start, end) of each UFF dataset, delimiters included; a text mesh's lines when there are none."""
    marks = [(m.start(), m.end()) for m in DELIMITER.finditer(data)]
    spans = [(a[0], min(b[1] + 1, len(data))) for a, b in zip(marks[::2], marks[1::2])]
    if spans:
        return spans
    starts = _lines(data)
    return list(zip(starts[:-1], starts[1:]))


def _facets(data: bytes) -> list[tuple[int, int]]:
    """A binary STL's 50-byte facet records, or the file's datasets / lines."""
    if is_binary_stl(data):
        return [(84 + 50 * k, 134 + 50 * k) for k in range((len(data) - 84) // 50)]
    return _datasets(data)


def is_binary_stl(data: bytes) -> bool:
    return len(data) >= 84 and 84 + 50 * struct.unpack_from("<I", data, 80)[0] == len(data)


def flip_bytes(data: bytes, rng: random.Random) -> bytes:
    out = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        if out:
            out[rng.randrange(len(out))] ^= rng.randint(1, 255)
    return bytes(out)


def truncate_at_record(data: bytes, rng: random.Random) -> bytes:
    """Cut at the start or end of a record (dataset or facet), or in its middle line."""
    spans = _facets(data)
    start, end = rng.choice(spans) if spans else (0, len(data))
    return data[: rng.choice([start, end, (start + end) // 2])]


def truncate_at_line(data: bytes, rng: random.Random) -> bytes:
    return data[: rng.choice(_lines(data))]


def swap_records(data: bytes, rng: random.Random) -> bytes:
    spans = _facets(data)
    if len(spans) < 2:
        return data
    (a0, a1), (b0, b1) = sorted(rng.sample(spans, 2))
    return data[:a0] + data[b0:b1] + data[a1:b0] + data[a0:a1] + data[b1:]


def duplicate_record(data: bytes, rng: random.Random) -> bytes:
    spans = _facets(data)
    if not spans:
        return data + data
    start, end = rng.choice(spans)
    where = rng.choice([end, len(data), spans[0][0]])
    return data[:where] + data[start:end] + data[where:]


def empty_record(data: bytes, rng: random.Random) -> bytes:
    """A dataset with nothing between its delimiter and number lines and its end, or a zero-byte facet."""
    spans = _facets(data)
    if not spans:
        return b""
    start, end = rng.choice(spans)
    block = data[start:end]
    if block.startswith(b"    -1"):
        number = block.split(b"\n")[1] if block.count(b"\n") > 1 else b"    58"
        return data[:start] + b"    -1\n" + number + b"\n    -1\n" + data[end:]
    return data[:start] + bytes(end - start) + data[end:]


def _header_tokens(data: bytes, pattern: re.Pattern, rng: random.Random) -> list[re.Match]:
    """Tokens of one record's first dozen lines (where UFF type fields and counts live) or of the file."""
    spans = _datasets(data)
    start, end = rng.choice(spans) if spans else (0, len(data))
    head = data[start:end]
    cut = _lines(head)[min(14, len(_lines(head)) - 1)]
    return [m for m in pattern.finditer(data, start, start + cut)]


def _replace(data: bytes, match: re.Match, text: bytes) -> bytes:
    return data[: match.start()] + text + data[match.end() :]


def wrong_type_field(data: bytes, rng: random.Random) -> bytes:
    """An integer field of a header (function type, data type, direction code, unit code) set to another small
    integer."""
    tokens = _header_tokens(data, INTEGER, rng)
    if not tokens:
        return data
    return _replace(data, rng.choice(tokens), str(rng.choice([-4, -3, -1, 0, 1, 2, 3, 4, 5, 6, 7, 9, 12])).encode())


def absurd_count(data: bytes, rng: random.Random) -> bytes:
    """A header integer (a count, a number of points, a byte count) set to an absurd value; a binary STL's facet
    count or a PLY's element count."""
    if is_binary_stl(data):
        return data[:80] + struct.pack("<I", rng.choice([0, 1, 2**32 - 1, 2**31, 10**9])) + data[84:]
    tokens = _header_tokens(data, INTEGER, rng)
    if not tokens:
        return data
    return _replace(data, rng.choice(tokens), rng.choice(ABSURD))


def non_ascii(data: bytes, rng: random.Random) -> bytes:
    """Non-ASCII text (UTF-8, Latin-1 bytes, NUL, a BOM) put into a line."""
    text = rng.choice(NON_ASCII) * rng.randint(1, 4)
    raw = text.encode(rng.choice(["utf-8", "latin-1", "utf-16"]), errors="replace")
    where = rng.choice(_lines(data))
    return data[:where] + raw + data[where:]


def nan_inf(data: bytes, rng: random.Random) -> bytes:
    """A numeric field set to NaN or an infinity: a text token, or the bits of a binary float."""
    tokens = list(NUMBER.finditer(data))
    if tokens and not is_binary_stl(data) and rng.random() < 0.8:
        return _replace(data, rng.choice(tokens), rng.choice(SPECIAL))
    if len(data) <= 8:
        return data
    fmt = rng.choice(["<f", "<d", ">f", ">d"])
    value = struct.pack(fmt, rng.choice(FLOATS))
    offset = 84 + 12 + 4 * rng.randrange(9) + 50 * rng.randrange(max((len(data) - 134) // 50, 1))
    if not is_binary_stl(data):
        offset = rng.randrange(len(data) - len(value))
    offset = min(offset, len(data) - len(value))
    return data[:offset] + value + data[offset + len(value) :]


def delete_line(data: bytes, rng: random.Random) -> bytes:
    starts = _lines(data)
    k = rng.randrange(len(starts) - 1) if len(starts) > 1 else 0
    return data[: starts[k]] + data[starts[k + 1] :] if len(starts) > 1 else data


MUTATIONS = (
    flip_bytes,
    truncate_at_record,
    truncate_at_line,
    swap_records,
    duplicate_record,
    empty_record,
    wrong_type_field,
    absurd_count,
    non_ascii,
    nan_inf,
    delete_line,
)


def mutate(data: bytes, rng: random.Random, steps: int) -> tuple[bytes, list[str]]:
    """``steps`` mutations drawn with ``rng``, applied in turn; the bytes and the mutations' names."""
    names = []
    for _ in range(steps):
        mutation = rng.choice(MUTATIONS)
        data = mutation(data, rng)
        names.append(mutation.__name__)
    return data, names


def fixture_uffs() -> list[Path]:
    return sorted(p for p in FIXTURE_UFF.iterdir() if p.suffix.lower() in (".uff", ".unv"))


def fixture_meshes() -> list[Path]:
    return sorted(p for p in FIXTURE_MESHES.iterdir() if p.suffix.lower() == ".stl")


def own_uffs(folder: Path) -> list[Path]:
    """A small virtual test (the bundled structure, 6 × 3 FRFs, rigid, a soft cord, 1 % noise, 100 lines)
    written as a lab exports it, as 58b with nodes in 2411, and in inches without the DC line."""
    from conftest import bundled

    from massline.placement.hand_layouts import structure_exciters, structure_sensors
    from massline.uff.writer import write_uff
    from massline.virtual.suspension import Cord, Suspension
    from massline.virtual.acquisition import Acquisition, run

    body = bundled("structure").nominal
    cord = Suspension(cords=(Cord.soft(body.cog + [0, 0, 0.15], body.mass),))
    recording, _ = run(body, structure_sensors(), structure_exciters(), None, cord, setup=Acquisition(lines=100))
    styles = {
        "lab.uff": dict(units="MM", acceleration="g"),
        "binary.uff": dict(binary=True, nodes_dataset=2411),
        "inches.uff": dict(units="IN", acceleration="g"),
    }
    paths = []
    for name, options in styles.items():
        write_uff(folder / name, recording, force=True, **options)
        paths.append(folder / name)
    return paths


def own_meshes(folder: Path) -> list[tuple[Path, str]]:
    """The bundled bodies exported as binary STL, ASCII STL, OBJ and PLY: (path, units)."""
    import trimesh

    from massline.meshes import BUNDLED

    paths = []
    for name, kind in (("plate", "stl"), ("bracket", "stl_ascii"), ("structure", "obj"), ("bracket", "ply")):
        mesh = trimesh.load(BUNDLED[name].path, force="mesh")
        suffix = "stl" if kind.startswith("stl") else kind
        path = folder / f"{name}-{kind}.{suffix}"
        mesh.export(path, file_type=kind)
        paths.append((path, "m"))
    return paths


FIXTURE_MESH_UNITS = json.loads((FIXTURE_MESHES / "units.json").read_text())  # file: units (SOURCES.md)
