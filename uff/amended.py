"""A Universal File written again with its channels amended: each dataset as it came but what the amendment changes.

What changes (:class:`Amendment`, in the file's own terms):

- the FRF records (58, function type 4) of sensor row t: their values times t's factor at each of their lines
  (a gain, a chain's factor of frequency), in the file's units (every FRF kind is the accelerance times a factor
  per line, so one factor serves them all); written again as ascii E20.12 or binary doubles, as the record was;
- rows whose recorded data belong to another row (a swap): each record's data, with its coherence record (function
  type 6), go to the record of the row they belong to; the ID lines and the labels stay with their place;
- the labels of record 6 (response and reference node and direction code), the nodes of 15/2411 and a dataset
  of new coordinate systems (18 beside 15, 2420 beside 2411) for channels whose lines changed
  (:mod:`.channel_geometry`);
- header records (151) after the file's own header (or first, when it has none), one per entry of the
  amendment's ``header``, its text split over their 80-column lines (ascii).

Everything else (units, the file's 151, other datasets, the 1858 qualifiers, coherence, the records' ID lines,
unchanged records byte for byte) is kept. The file is written whole or not at all.
"""

from __future__ import annotations

import textwrap
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError
from massline.core.files import atomic_file, claim_output
from massline.uff.channel_geometry import Placement
from massline.uff.datasets import RawDataset, parse, split
from massline.uff.runs import lines_in
from massline.uff.function_records import ascii_values, binary_values
from massline.uff.writer import COLOR

FRF, COHERENCE = 4, 6
TEXT = 80  # columns of a 151 text line
ASCII = {"±": "+/-", "−": "-", "µ": "u", "°": " deg", "×": "x", "→": "->", "÷": "/", "ω": "w", "τ": "tau", "σ": "sigma",
         "²": "^2", "–": "-", "—": "-", "θ": "theta", "δ": "delta", "≈": "~", "√": "sqrt", "χ": "chi", "ζ": "zeta",
         "α": "alpha", "γ": "gamma", "·": "*", "’": "'", "…": "..."}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Amendment:
    """What a file's amended copy changes.

    Attributes
    ----------
    frequencies : (n_f,) array
        Hz: the axis of ``factors`` (the union of the file's FRF axes, as :func:`.grid.to_recording` reads it).
    factors : (n_s, n_f) complex array
        Each sensor row's records' values are multiplied by it.
    sources : (n_s,) int array
        Row t's records hold the data recorded under row ``sources[t]``'s label.
    placement : Placement
        The labels of every channel, keyed ("response", i) and ("reference", j), and the nodes and coordinate
        systems written anew.
    sensor_labels, exciter_labels : tuple of Channel
        The channels of rows i and columns j as the file (or the runs' files together) labels them.
    header : tuple of (title, text)
        One entry per header record: a title (80 columns) and its text.
    """

    frequencies: np.ndarray
    factors: np.ndarray
    sources: np.ndarray
    placement: Placement
    sensor_labels: tuple
    exciter_labels: tuple
    header: tuple = ()


def ascii_text(text: str) -> str:
    """``text`` on one ascii line: the symbols a sentence of the diagnosis uses spelled out, the rest '?'."""
    for symbol, spelled in ASCII.items():
        text = text.replace(symbol, spelled)
    return " ".join(text.split()).encode("ascii", "replace").decode()


def header_151(title: str, lines: list[str], stamp: str) -> bytes:
    """One dataset 151: ``title`` as the model name, ``lines`` (two at most) as its description and its database
    application's name; the program massline; dates ``stamp``."""
    date, clock = stamp.split()
    description, application = (lines + ["NONE", "NONE"])[:2]
    when = f"{date:<10s}{clock:<10s}"
    records = [title, description, application, f"{when}{0:10d}{0:10d}{0:10d}", when,
               "massline diagnose --write-corrected", when]  # fmt: skip
    text = "".join(f"{r[:TEXT]:<80s}\n" for r in records)
    return f"{-1:6d}\n{151:6d}\n{text}{-1:6d}\n".encode("ascii")


def headers(entries, stamp: str) -> bytes:
    """The header records of ``entries`` ((title, text) each): the text wrapped on 80 columns, two lines to a
    record, continued in further records titled '(2/3)' and so on."""
    out = b""
    for title, text in entries:
        wrapped = textwrap.wrap(ascii_text(text), TEXT) or ["NONE"]
        parts = [wrapped[k : k + 2] for k in range(0, len(wrapped), 2)]
        for k, part in enumerate(parts):
            more = f" ({k + 1}/{len(parts)})" if len(parts) > 1 else ""
            out += header_151(ascii_text(title)[: TEXT - len(more)] + more, part, stamp)
    return out


def raw(data: bytes, block: RawDataset) -> bytes:
    """A dataset's bytes as they came, ending its closing delimiter's line."""
    text = data[slice(*block.span)]
    return text if text.endswith(b"\n") else text + b"\n"


def with_channels(line: str, response, reference) -> str:
    """Record 6 with its response and reference node and direction code (I10, I4 each) set."""
    line = line.ljust(TEXT)
    at, to = f"{response.node:10d}{response.code:4d}", f"{reference.node:10d}{reference.code:4d}"
    return line[:41] + at + line[55:66] + to


def record_58(labelled: RawDataset, data: RawDataset, function, response, reference, factor) -> bytes:
    """A 58 record: ID lines from ``labelled`` with record 6 naming ``response`` / ``reference``; records 7–11 and
    the values from ``data`` (``function`` parsed from it), times ``factor`` at each line (None: as they came)."""
    ids, _ = labelled.head(6)
    lines, rest = data.head(11)
    head = ids[:5] + [with_channels(ids[5], response, reference)]
    binary = data.binary
    if factor is None:
        payload = binary[1] if binary else rest.encode("latin-1")
        order = binary[0] if binary else "<"
    else:
        values = function.values * factor
        complex_ = np.iscomplexobj(values)
        parts = [values.real, values.imag] if complex_ else [values.real]
        even = int(lines[6].split()[2]) == 1
        payload = (binary_values if binary else ascii_values)(function.frequencies, parts, even)
        lines[6] = f"{6 if complex_ else 4:10d}" + lines[6][10:]
        order = "<"
    text = "".join(f"{line}\n" for line in head + lines[6:11])
    if binary:
        ident = f"{58:6d}b{1 if order == '<' else 2:6d}{2:6d}{11:12d}{len(payload):12d}{0:6d}{0:6d}{0:12d}{0:12d}\n"
    else:
        ident = f"{58:6d}\n"
    tail = b"" if payload.endswith(b"\n") else b"\n"
    return f"{-1:6d}\n{ident}{text}".encode("latin-1") + payload + tail + f"{-1:6d}\n".encode()


def node_lines(block: RawDataset, placement: Placement, length: float) -> bytes:
    """Dataset 15 or 2411 with the moved nodes written again (in the global system) and the added ones after."""
    lines, out = block.lines, []
    per = 2 if block.number == 2411 else 1
    for k in range(0, len(lines), per):
        fields = lines[k].split()
        node = int(fields[0]) if fields else None
        place = placement.moved.get(node)
        out += lines[k : k + per] if place is None else node_record(block.number, place, int(fields[3]), length)
    for place in placement.added:
        out += node_record(block.number, place, COLOR, length)
    text = "".join(f"{line}\n" for line in out)
    return f"{-1:6d}\n{block.number:6d}\n{text}{-1:6d}\n".encode("latin-1")


def node_record(number: int, place, color: int, length: float) -> list[str]:
    """A node's lines of dataset 15 (4I10, 1P3E13.5) or 2411 (4I10; 1P3D25.16), in file length units."""
    x, y, z = np.asarray(place.point) * length
    ids = f"{place.node:10d}{0:10d}{place.system:10d}{color:10d}"
    if number == 2411:
        return [ids, f"{x:25.16E}{y:25.16E}{z:25.16E}"]
    return [f"{ids}{x:13.5E}{y:13.5E}{z:13.5E}"]


def systems_dataset(placement: Placement, points: dict, nodes_dataset: int, length: float) -> bytes:
    """The new coordinate systems: dataset 18 (origin, a point on +x, one in the +xz plane; E13.5) beside nodes
    in 15, 2420 (axes and origin as rows; D25.16) beside 2411; each at its node's point, in file length units."""
    if not placement.systems:
        return b""
    lines = [] if nodes_dataset == 15 else [f"{1:10d}", "massline corrections"]
    for label, frame in placement.systems.items():
        origin = np.asarray(points.get(label, np.zeros(3))) * length
        if nodes_dataset == 15:
            x_point = origin + frame[:, 0] * length
            values = np.concatenate([origin, x_point, x_point + frame[:, 2] * length])
            lines += [f"{label:10d}{0:10d}{0:10d}{COLOR:10d}{1:10d}", f"SYS{label}"]
            lines += ["".join(f"{v:13.5E}" for v in values[:6]), "".join(f"{v:13.5E}" for v in values[6:])]
        else:
            lines += [f"{label:10d}{0:10d}{COLOR:10d}", f"SYS{label}"]
            lines += ["".join(f"{v:25.16E}" for v in row) for row in (*frame.T, origin)]
    number = 18 if nodes_dataset == 15 else 2420
    text = "".join(f"{line}\n" for line in lines)
    return f"{-1:6d}\n{number:6d}\n{text}{-1:6d}\n".encode("latin-1")


def amended_bytes(source: Path, amendment: Amendment) -> bytes:
    """The file at ``source`` (one run's of several, or the whole test's) with ``amendment`` made (module
    docstring). A swap's records restored to their places within the file; a record whose place is in another
    run's file keeps its own, labelled as the row it belongs to. A file without nodes keeps its records' labels'
    geometry where the runs' files with nodes hold it."""
    data, name = source.read_bytes(), str(source)
    blocks = split(data, name)
    labels_of = amendment.sensor_labels
    rows = {label: i for i, label in enumerate(labels_of)}
    columns = {label: j for j, label in enumerate(amendment.exciter_labels)}
    length = next((parse(b, name) for b in blocks if b.number == 164), (1.0, 1.0))[0]
    functions = {k: parse(b, name)[0] for k, b in enumerate(blocks) if b.number == 58}
    measured = {k: f for k, f in functions.items() if f.type in (FRF, COHERENCE) and f.response in rows
                and f.reference in columns}  # fmt: skip
    where = {}
    for k, f in measured.items():
        where.setdefault((f.type, f.response, f.reference), k)
    to_row = np.argsort(amendment.sources)  # the row whose place the data of each row go to
    out: list[list[bytes]] = [[] for _ in blocks]
    labels = amendment.placement.labels
    for k, f in measured.items():
        t, j = int(to_row[rows[f.response]]), columns[f.reference]
        at = where.get((f.type, labels_of[t], f.reference), k)
        factor = amendment.factors[t, lines_in(amendment.frequencies, f.frequencies)] if f.type == FRF else None
        if factor is not None and np.all(factor == 1):
            factor = None
        response, reference = labels[("response", t)], labels[("reference", j)]
        if at == k and factor is None and (response, reference) == (f.response, f.reference):
            out[at].append(raw(data, blocks[k]))
        else:
            out[at].append(record_58(blocks[at], blocks[k], f, response, reference, factor))
    stamp = time.strftime("%d-%b-%y %H:%M:%S")
    first_header = next((k for k, b in enumerate(blocks) if b.number == 151), None)
    first_nodes = next((k for k, b in enumerate(blocks) if b.number in (15, 2411)), None)
    points = {p.system: p.point for p in [*amendment.placement.moved.values(), *amendment.placement.added]}
    written = b"" if first_header is not None else headers(amendment.header, stamp)
    for k, block in enumerate(blocks):
        if k == first_nodes:
            written += systems_dataset(amendment.placement, points, block.number, length)
        if block.number in (15, 2411) and k == first_nodes:
            written += node_lines(block, amendment.placement, length)
        elif k in measured:
            written += b"".join(out[k])
        else:
            written += raw(data, block)
        if k == first_header:
            written += headers(amendment.header, stamp)
    return written


def write_amended(sources, paths, amendment: Amendment, *, force: bool = False) -> list[Path]:
    """Write each file of ``sources`` (one, or each run's) with ``amendment`` made (module docstring) to the path of
    ``paths`` beside it, each whole or not at all; every path is checked before any is written: an existing one
    only with ``force``, never one of the sources. Returns ``paths``."""
    sources, paths = [Path(s) for s in sources], [Path(p) for p in paths]
    for path in paths:
        if path.exists() and any(path.resolve() == s.resolve() for s in sources):
            raise MasslineError(f"{path} is a recording read: write the corrected recording to another file")
        claim_output(path, force)
    for source, path in zip(sources, paths):
        written = amended_bytes(source, amendment)
        with atomic_file(path) as temporary:
            temporary.write_bytes(written)
    return paths
