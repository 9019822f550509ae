"""Adams dataset export, read by a parser written here from the Adams/Solver (C++) statements reference: the
first line is the title, '!' starts a comment, a line starting with ',' continues the statement above;
``NAME/id, ARG = v1, v2, …``; PART's ``IP = Ixx, Iyy, Izz, Ixy, Ixz, Iyz`` about the CM marker with the
products as positive integrals (Ixy = +∫xy dm), so the tensor is [[Ixx, −Ixy, −Ixz], [−Ixy, Iyy, −Iyz], …];
MARKER's ``QP`` its origin in the part's frame (ground's, no QG or REULER); UNITS names the units."""

import re

import numpy as np
import pytest
from export_bodies import assert_same_body, measured, rigid_bodies

from massline.export import export_text
from massline.export.units import UNITS

ADAMS_UNITS = {"METER": 1.0, "MILLIMETER": 1e3, "KILOGRAM": 1.0, "TONNE": 1e-3}  # per metre, per kilogram


def statements(text: str) -> list[tuple[str, str, dict]]:
    """(name, id, {argument: [values]}) of each statement after the title line, continuations joined."""
    joined: list[str] = []
    for line in text.splitlines()[1:]:
        line = line.split("!", 1)[0].rstrip()
        if not line:
            continue
        if line.startswith(","):
            joined[-1] += line
        else:
            joined.append(line)
    found = []
    for statement in joined:
        name, _, rest = statement.partition("/")
        parts = re.split(r",\s*(?=[A-Z]+\s*=|[A-Z]+\s*(?:,|$))", rest.strip())
        ident = parts.pop(0).strip() if parts[0].strip().isdigit() else ""  # UNITS/ has no id
        arguments: dict[str, list[str]] = {}
        for part in parts:
            key, _, values = part.partition("=")
            arguments[key.strip()] = [v.strip() for v in values.split(",") if v.strip()]
        found.append((name.strip(), ident, arguments))
    return found


def read_by_the_manual(text: str) -> tuple[float, np.ndarray, np.ndarray]:
    """The moving part's mass, its CM marker's position and its inertia tensor, converted to SI by UNITS."""
    found = statements(text)
    (units,) = [a for n, _, a in found if n == "UNITS"]
    length, mass = ADAMS_UNITS[units["LENGTH"][0]], ADAMS_UNITS[units["MASS"][0]]
    assert units["FORCE"] == ["NEWTON"] and units["TIME"] == ["SECOND"]
    (part,) = [a for n, _, a in found if n == "PART" and "GROUND" not in a]
    markers = {i: a for n, i, a in found if n == "MARKER"}
    cm = markers[part["CM"][0]]
    assert "IM" not in part and "QG" not in part and "REULER" not in cm
    xx, yy, zz, xy, xz, yz = (float(v) for v in part["IP"])
    J = np.array([[xx, -xy, -xz], [-xy, yy, -yz], [-xz, -yz, zz]])
    position = np.array([float(v) for v in cm["QP"]])
    return float(part["MASS"][0]) / mass, position / length, J / (mass * length**2)


@pytest.mark.parametrize("name", ["bracket", "far"])
@pytest.mark.parametrize("units", list(UNITS))
def test_the_manuals_layout_reads_the_body_back(name, units):
    body = rigid_bodies()[name]
    text = export_text(measured(body), "body.adm", UNITS[units])
    assert_same_body(*read_by_the_manual(text), body, rtol=1e-9)
    assert text.splitlines()[-1] == "END" and all(len(line) <= 80 for line in text.splitlines())


def test_the_products_of_inertia_are_positive_integrals():
    """Adams's Ixy = +∫xy dm = −J_xy: the bracket's negative J_xy is written positive."""
    body = rigid_bodies()["bracket"]
    (part,) = [a for n, _, a in statements(export_text(measured(body), "b.adm")) if n == "PART" and "IP" in a]
    assert body.inertia_cog[0, 1] < 0 and float(part["IP"][3]) == pytest.approx(-body.inertia_cog[0, 1], rel=1e-9)
