"""Nastran bulk data export: a GRID and a CONM2 in large-field format.

Read back two ways: by a parser written here from the MSC Nastran Quick Reference Guide (large-field columns;
CONM2's inertia matrix [[I11, −I21, −I31], [−I21, I22, −I32], [−I31, −I32, I33]]), and by pyNastran itself —
its CONM2 ``Mass()``, ``Centroid()`` and ``Inertia()`` (the card, not ``mass_properties()``, which adds a
CONM2's −I21 into an Ixy that for point masses is +Σ m x y). pyNastran 1.4 pins numpy < 2 (massline needs ≥ 2
through cvxpy), so it runs in a venv of its own, made once under ~/.cache and kept; the test is skipped, saying
why, where pip cannot install it.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from export_bodies import assert_same_body, measured, rigid_bodies

from massline.export import export_text, write_export
from massline.export.nastran import bulk_data
from massline.export.units import SI, UNITS

VENV = Path.home() / ".cache" / "massline-test-pynastran"
READ = """
import json, sys
from pyNastran.bdf.bdf import BDF
found = {}
for path in sys.argv[1:]:
    model = BDF(debug=None)
    model.read_bdf(path, punch=True, xref=True)
    (conm2,) = model.masses.values()
    found[path] = {"card": conm2.type, "mass": float(conm2.Mass()), "centroid": [float(v) for v in conm2.Centroid()],
                   "inertia": [[float(v) for v in row] for row in conm2.Inertia()]}
print(json.dumps(found))
"""


def large_fields(text: str) -> dict[str, list[str]]:
    """Each entry's fields by the QRG's large-field rules: columns 1–8 the name ('NAME*', a continuation '*'),
    then four fields of 16 columns; '$' lines are comments."""
    cards: dict[str, list[str]] = {}
    name = None
    for line in text.splitlines():
        if line.startswith("$") or not line.strip():
            continue
        head = line[:8].strip()
        fields = [line[8 + 16 * k : 24 + 16 * k].strip() for k in range(4)]
        if head != "*":
            assert head.endswith("*"), line
            name = head[:-1]
            cards[name] = []
        cards[name] += fields
    return cards


def read_by_the_manual(text: str, units=SI) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, CoG = GRID + (X1, X2, X3) (CID 0: basic) and the inertia matrix of CONM2 remark, back in SI."""
    cards = large_fields(text)
    grid, conm2 = cards["GRID"], cards["CONM2"]
    assert grid[0] == conm2[1] and conm2[2] == "0" and grid[1] == "0"
    position = np.array([float(v) for v in grid[2:5]])
    offset = np.array([float(v) for v in conm2[4:7]])
    I11, I21, I22, I31, I32, I33 = (float(v) for v in conm2[8:14])
    J = np.array([[I11, -I21, -I31], [-I21, I22, -I32], [-I31, -I32, I33]])
    length, mass = units.per_metre, units.per_kilogram
    return float(conm2[3]) / mass, (position + offset) / length, J / (mass * length**2)


@pytest.mark.parametrize("name", ["bracket", "far"])
@pytest.mark.parametrize("units", list(UNITS))
def test_the_manuals_layout_reads_the_body_back(name, units):
    body = rigid_bodies()[name]
    text = export_text(measured(body), "body.bdf", UNITS[units])
    assert_same_body(*read_by_the_manual(text, UNITS[units]), body, rtol=1e-9)
    assert all(len(line) <= 80 for line in text.splitlines())


def test_the_grid_may_sit_at_the_reference_point():
    """GRID at the origin: the CONM2's offsets carry the CoG, and the body read back is the same."""
    body = rigid_bodies()["far"]
    text = bulk_data(measured(body), SI, reference=np.zeros(3))
    assert_same_body(*read_by_the_manual(text), body, rtol=1e-9)
    assert np.allclose([float(v) for v in large_fields(text)["GRID"][2:5]], 0)


def test_the_products_of_inertia_are_written_with_nastrans_sign():
    """I21 = +∫xy dm = −J_xy: the bracket's J_xy is negative, so its CONM2 I21 is positive."""
    body = rigid_bodies()["bracket"]
    conm2 = large_fields(export_text(measured(body), "b.bdf"))["CONM2"]
    assert body.inertia_cog[0, 1] < 0 and float(conm2[9]) == pytest.approx(-body.inertia_cog[0, 1], rel=1e-9)


def pynastran() -> Path:
    """The python of a venv holding pyNastran and numpy < 2 (made once and kept); skip when pip cannot make it."""
    python = VENV / "bin" / "python"
    if (
        python.exists()
        and subprocess.run([python, "-c", "import pyNastran"], capture_output=True, check=False).returncode == 0
    ):
        return python
    steps = (
        [sys.executable, "-m", "venv", "--clear", VENV],
        [python, "-m", "pip", "install", "-q", "pyNastran", "numpy<2"],
    )
    for step in steps:
        try:
            made = subprocess.run(step, capture_output=True, check=False, text=True, timeout=900)
        except subprocess.TimeoutExpired:
            pytest.skip("pyNastran: pip took over 15 min (no PyPI?)")
        if made.returncode:
            pytest.skip(
                f"pyNastran could not be installed ({' '.join(map(str, step[:4]))}): {made.stderr.strip()[-300:]}"
            )
    return python


@pytest.mark.slow
def test_pynastran_reads_the_conm2_massline_wrote(tmp_path):
    bodies = rigid_bodies()
    written = {
        tmp_path / "bracket.bdf": (bodies["bracket"], SI, None),
        tmp_path / "far.dat": (bodies["far"], SI, None),
        tmp_path / "far_at_origin.bdf": (bodies["far"], SI, np.zeros(3)),
        tmp_path / "far_mm_t.bdf": (bodies["far"], UNITS["mm-t"], None),
    }
    for path, (body, units, reference) in written.items():
        path.write_text(bulk_data(measured(body), units, reference))
    write_export(measured(bodies["far"]), tmp_path / "far_mm_kg.bdf", UNITS["mm-kg"])
    written[tmp_path / "far_mm_kg.bdf"] = (bodies["far"], UNITS["mm-kg"], None)
    run = subprocess.run(
        [pynastran(), "-c", READ, *map(str, written)], capture_output=True, check=False, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    found = json.loads(run.stdout.strip().splitlines()[-1])
    for path, (body, units, _) in written.items():
        card = found[str(path)]
        length, mass = units.per_metre, units.per_kilogram
        inertia = np.array(card["inertia"]) / (mass * length**2)
        assert card["card"] == "CONM2"
        assert_same_body(card["mass"] / mass, np.array(card["centroid"]) / length, inertia, body, rtol=1e-9)
