"""Units of a Universal File as exporters write them: dataset 164's system and the FRF labels of dataset 58.

Dataset 164's factors are file units per SI unit: codes 1 (SI: m, N), 5 (mm, mN) and 7 (in, lbf). UFF has no
unit for g: its data type 12 means length/s² in the file's units, so an exporter that stores accelerance in g
per force unit says so only in the labels. Real files do it the same way: a vendor export in ladisk/pyuff's
``data/binary8byte.uff`` types its acceleration 12 with exponents 0 and the unit label "g"; ME'scope writes
"Gs/N", Testlab "g/N" (``notes/lab-realism.md`` §1). A reader that converts by type field and 164 alone reads
such a file 9.81 × wrong; this project's reader (:mod:`.frf_kind`) takes the scale from the labels first.
"""

from __future__ import annotations

from dataclasses import dataclass

G = 9.80665  # m/s² per g
LBF = 4.4482216152605  # N per lbf (exact, by definition)
INCH = 0.0254  # m per in
ACCELERATIONS = ("length", "g")  # accelerance written as length/s² per force unit, or as g per force unit


@dataclass(frozen=True)
class UnitSystem:
    """A UFF 164 unit system: file units per SI unit, and the labels written in dataset 58.

    Attributes
    ----------
    code : int
        Dataset 164's unit code.
    description : str
        Dataset 164's description.
    length, force : float
        File units per metre, per newton.
    length_label, force_label : str
        The labels of those units.
    g_force_label : str
        The force unit an exporter writes under g: "N" beside metric geometry, "lbf" beside inches.
    """

    code: int
    description: str
    length: float
    force: float
    length_label: str
    force_label: str
    g_force_label: str


UNITS = {
    "SI": UnitSystem(1, "SI: Meter (newton)", 1.0, 1.0, "m", "N", "N"),
    "MM": UnitSystem(5, "MM: mm (milli N)", 1e3, 1e3, "mm", "mN", "N"),
    "IN": UnitSystem(7, "IN: Inch (pound f)", 1 / INCH, 1 / LBF, "in", "lbf", "lbf"),
}
FORCE_UNITS = {"N": 1.0, "lbf": 1 / LBF}  # force units per newton


@dataclass(frozen=True)
class Characteristic:
    """Records 9 or 10 of dataset 58: specific data type, (length, force, temperature) exponents, labels."""

    data_type: int
    exponents: tuple[int, int, int]
    axis_label: str
    unit_label: str


@dataclass(frozen=True)
class AccelerationUnits:
    """How accelerance is written: the factor from (m/s²)/N to the file's numbers, and records 9 and 10."""

    factor: float
    numerator: Characteristic
    denominator: Characteristic


def accelerance_units(system: UnitSystem, acceleration: str = "length") -> AccelerationUnits:
    """Accelerance in ``system``: (length/s²)/force in the system's units, or g per its force unit.

    Parameters
    ----------
    system : UnitSystem
    acceleration : {"length", "g"}
        "length": types 12 over 13 with exponents 1 and 1, labels "mm/s^2" over "mN" (file units, as the type
        fields say); "g": types 12 over 13 with exponents 0 and labels "g" over "N" or "lbf", as exporters
        write g/N (the labels, not the 164 factors, give the scale).
    """
    if acceleration == "g":
        force = FORCE_UNITS[system.g_force_label]
        return AccelerationUnits(
            1 / (G * force),
            Characteristic(12, (0, 0, 0), "Acceleration", "g"),
            Characteristic(13, (0, 0, 0), "Force", system.g_force_label),
        )
    return AccelerationUnits(
        system.length / system.force,
        Characteristic(12, (1, 0, 0), "Acceleration", f"{system.length_label}/s^2"),
        Characteristic(13, (0, 1, 0), "Force", system.force_label),
    )
