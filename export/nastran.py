"""Nastran bulk data: a GRID and a CONM2 (concentrated mass, rigid-body form), in large-field format.

MSC Nastran Quick Reference Guide, CONM2: fields EID, G, CID, M, X1–X3 (the offset from the grid point to the
CoG, in the basic system when CID = 0), then I11, I21, I22, I31, I32, I33, the inertia about the CoG; remark
"the form of the inertia matrix about its center of gravity is [[I11, −I21, −I31], [−I21, I22, −I32],
[−I31, −I32, I33]] … only the magnitude of Iij should be supplied, the negative signs for the off-diagonal
terms are supplied automatically": I21 = +∫x₁x₂ dm is a product of inertia, minus the tensor's J_xy.

Large field (QRG, "Format of Bulk Data Entries"): an 8-column name ending in '*', four 16-column fields a
line, continuation lines starting with '*'; 16 columns keep ten significant digits, where the small field's
8 keep five — less than the identification's own precision.
"""

from __future__ import annotations

import numpy as np

from massline.export.header import commented, header_lines
from massline.export.units import Units

GRID_ID = 1
ELEMENT_ID = 1
CONVENTION = (
    "CONM2 I11 I21 I22 I31 I32 I33 with I21 = +int(xy dm) = -J_xy, I31 = -J_xz, I32 = -J_yz "
    "(MSC Nastran QRG, CONM2: the matrix [[I11, -I21, -I31], ...], signs supplied by Nastran)"
)


def large_real(value: float) -> str:
    """A real in a 16-column field: '-1.507476250E-04', ten significant digits."""
    return f"{float(value):16.9E}"


def large_card(name: str, fields: list[str]) -> str:
    """A large-field entry: '{name}*' and four 16-column fields a line, continuation lines marked '*'."""
    lines = []
    for k in range(0, len(fields), 4):
        first = f"{name}*" if k == 0 else "*"
        lines.append(f"{first:<8}" + "".join(f"{f:<16}" for f in fields[k : k + 4]))
    return "".join(line.rstrip() + "\n" for line in lines)


def conm2_inertia(J: np.ndarray) -> list[float]:
    """I11, I21, I22, I31, I32, I33 of a CONM2 from the inertia tensor J (tensor sign): products negated."""
    return [J[0, 0], -J[0, 1], J[1, 1], -J[0, 2], -J[1, 2], J[2, 2]]


def bulk_data(body, units: Units, reference: np.ndarray | None = None) -> str:
    """The GRID and CONM2 of ``body`` (a ``Body``) in ``units``.

    Parameters
    ----------
    body : Body
        Mass (kg), CoG (m) and inertia about the CoG (kg·m², tensor sign) in the frame of the recording.
    units : Units
        The deck's unit system (Nastran takes any consistent one; the comment names it).
    reference : ndarray (3,), optional
        Where the GRID sits, m, in the same frame (CONM2's X1–X3 then offset it to the CoG); the CoG by default.
    """
    cog = units.lengths(body.cog)
    grid = cog if reference is None else units.lengths(reference)
    grid_fields = [str(GRID_ID), "0", *map(large_real, grid)]
    conm2 = [str(ELEMENT_ID), str(GRID_ID), "0", large_real(units.masses(body.mass))]
    conm2 += [*map(large_real, cog - grid), ""]
    conm2 += [large_real(v) for v in conm2_inertia(units.inertias(body.inertia))]
    return (
        commented(header_lines(body, units, CONVENTION), "$ ")
        + large_card("GRID", grid_fields)
        + large_card("CONM2", conm2)
    )
