"""massline.export — the measured body in the formats of the tools that use it.

:class:`~.body.Body` is a body as measured (mass, CoG, inertia about the CoG, their 1-σ, what was measured);
one module per format turns it into text (a pure function ``Body``, :class:`~.units.Units` → str):
:mod:`.nastran` (GRID + CONM2), :mod:`.abaqus` (``*MASS`` + ``*ROTARY INERTIA``), :mod:`.adams` (PART),
:mod:`.urdf`, :mod:`.sdf` and :mod:`.mjcf` (``<inertial>``), :mod:`.csv_row` (one row ± 1-σ); :mod:`.formats`
picks one by a file's suffix, refuses what it cannot hold and writes the file atomically. Each file says in
comments what was measured, with what ±, in which frame and units, by which massline, and how its format
signs the products of inertia (:mod:`.header`). It imports nothing of the project but :mod:`massline.core`.
"""

from massline.export.body import PLATE_UNOBSERVED, Body
from massline.export.formats import FORMATS, check_export, check_observed, export_text, format_of, write_export
from massline.export.units import SI, UNITS, Units, unit_system

__all__ = [
    "FORMATS",
    "PLATE_UNOBSERVED",
    "SI",
    "UNITS",
    "Body",
    "Units",
    "check_export",
    "check_observed",
    "export_text",
    "format_of",
    "unit_system",
    "write_export",
]
