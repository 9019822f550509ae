"""The UFF reader on files written here: round trips, kind and unit decisions, coordinate systems, hardened errors."""

import re

import numpy as np
import pytest
import pyuff
from scipy.spatial.transform import Rotation

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.uff.frf_kind import units
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.recording import Recording
from massline.uff.writer import write_uff

ROTATED = Rotation.from_euler("xyz", [20, -35, 50], degrees=True).as_matrix()
FREQUENCIES = 3.0 + 0.5 * np.arange(395)  # Hz, 3-200
SENSORS = [(1, 1), (2, 2), (3, 3)]  # (node, code) of the synthetic files, all nodes in the global frame
EXCITERS = [(11, 1), (12, 2), (13, 3)]
POINTS = {1: [0.1, 0, 0], 2: [0, 0.2, 0], 3: [0, 0, 0.3], 11: [0.2, 0.1, 0], 12: [0, 0.1, 0.2], 13: [0.1, 0, 0.2]}


def accelerance(f, amplitude):
    """A suspended body's accelerance, (m/s²)/N: mass line ``amplitude``, 1.2 Hz suspension, 600 Hz elastic mode."""
    w, ws, we = 2 * np.pi * f, 2 * np.pi * 1.2, 2 * np.pi * 600.0
    return -(w**2) * (amplitude / (ws**2 - w**2 + 0.1j * ws * w) + 0.3 * amplitude / (we**2 - w**2 + 0.02j * we * w))


def grid(f=FREQUENCIES):
    """Accelerance of every synthetic sensor-exciter pair, (3, 3, n_f)."""
    return np.array([[accelerance(f, 0.2 + 0.1 * i - 0.05 * j) for j in range(3)] for i in range(3)])


def function(response, reference, data, f=FREQUENCIES, types=(12, 13), labels=("NONE", "NONE"), **extra):
    """A dataset-58 dict for pyuff's writer: an FRF (function type 4) on an even axis unless told."""
    return {
        "type": 58,
        "binary": 0,
        "func_type": 4,
        "rsp_node": response[0],
        "rsp_dir": response[1],
        "ref_node": reference[0],
        "ref_dir": reference[1],
        "abscissa_spacing": 1,
        "abscissa_spec_data_type": 18,
        "abscissa_axis_units_lab": "Hz",
        "ordinate_spec_data_type": types[0],
        "orddenom_spec_data_type": types[1],
        "ordinate_axis_units_lab": labels[0],
        "orddenom_axis_units_lab": labels[1],
        "x": f,
        "data": data,
        **extra,
    }


def nodes(scale=1.0):
    """Dataset 15 of the synthetic nodes, coordinates multiplied by ``scale`` (file units per metre)."""
    x, y, z = (np.array(list(POINTS.values()), dtype=float) * scale).T
    n = len(POINTS)
    return pyuff.prepare_15(
        node_nums=list(POINTS), def_cs=[0] * n, disp_cs=[0] * n, color=[8] * n, x=list(x), y=list(y), z=list(z)
    )


def write(path, functions):
    """A Universal File of the synthetic nodes and ``functions``, written by pyuff."""
    pyuff.UFF(str(path)).write_sets([nodes(), *functions], mode="overwrite")
    return path


def full_set(data, **options):
    """Every synthetic sensor against every exciter."""
    return [function(s, e, data[i, j], **options) for i, s in enumerate(SENSORS) for j, e in enumerate(EXCITERS)]


def assert_close(found, expected, rtol):
    assert np.abs(found - expected).max() <= rtol * np.abs(expected).max()


# ---- round trip with the virtual-test writer


def virtual_recording(f=2.0 + 0.25 * np.arange(40)) -> Recording:
    """Two global and one oblique uniaxial sensor (two at one point), a rotated triaxial; three oblique hits."""
    points = [[0.1, 0.2, 0.3], [0.1, 0.2, 0.3], [0.3, -0.1, 0.2]] + [[-0.15, -0.25, 0.05]] * 3
    s = Lines(points, [[1, 0, 0], [0, 0, -1], [1, 2, -0.5], *ROTATED.T], [-1, -1, -1, 0, 0, 0])
    e = Lines([[0.25, 0.1, -0.05], [0.1, 0.2, 0.3], [-0.3, 0, 0.15]], [[0.3, -0.4, 0.866], [0, 1, 0], [-1, 0.2, 0.1]])
    rng = np.random.default_rng(3)
    shape = (len(s), len(e), len(f))
    frf = rng.normal(size=shape) + 1j * rng.normal(size=shape)
    return Recording(f, frf, s, e, coherence=rng.uniform(0.5, 1.0, size=shape), description="rig 3")


@pytest.mark.parametrize(
    "options, geometry_tol, value_tol",
    [
        ({"nodes_dataset": 15, "binary": False}, 5e-6, 1e-11),  # 15/18 are E13.5, ascii 58 is E20.12
        ({"nodes_dataset": 15, "binary": True}, 5e-6, 0.0),
        ({"nodes_dataset": 2411, "binary": False}, 1e-15, 1e-11),  # 2411/2420 are D25.16
        ({"nodes_dataset": 2411, "binary": True, "units": "MM"}, 1e-15, 1e-15),
    ],
)
def test_round_trip_with_the_virtual_test_writer(tmp_path, options, geometry_tol, value_tol):
    written = virtual_recording()
    write_uff(tmp_path / "virtual.uff", written, force=False, node_systems=True, **options)
    contents = read_uff(tmp_path / "virtual.uff")
    found = to_recording(contents)
    assert contents.warnings == [] and {(f.kind, f.rule) for f in contents.frfs} == {("accelerance", "type field")}
    np.testing.assert_array_equal(found.frequencies, written.frequencies)
    assert_close(found.frf, written.frf, value_tol)
    assert_close(found.coherence, written.coherence, value_tol)
    for got, want in ((found.sensors, written.sensors), (found.exciters, written.exciters)):
        np.testing.assert_allclose(got.points, want.points, atol=geometry_tol)
        np.testing.assert_allclose(got.directions, want.directions, atol=2 * geometry_tol)
        np.testing.assert_array_equal(got.triaxial, want.triaxial)
    assert found.description == "massline virtual test rig 3"


def test_uneven_axis_round_trip(tmp_path):
    """Uneven abscissa: ascii (E13.5 abscissa) and binary (single-precision abscissa, double values)."""
    written = virtual_recording(np.array([1.0, 1.5, 2.5, 4.0, 6.0, 8.5, 11.5]))
    for binary in (False, True):
        write_uff(tmp_path / f"uneven{binary}.uff", written, binary=binary)
        found = to_recording(read_uff(tmp_path / f"uneven{binary}.uff"))
        np.testing.assert_array_equal(found.frequencies, written.frequencies)
        assert_close(found.frf, written.frf, 1e-11)


# ---- kinds and units


KIND_CASES = {  # stored kind: (n: it is accelerance / (iω)^n, type fields right, wrong, unit labels, whole unit)
    "accelerance": (0, (12, 13), (8, 13), ("m/s^2", "N"), "(m/s^2)/N"),
    "mobility": (1, (11, 13), (12, 13), ("m/s", "N"), "(m/s)/N"),
    "receptance": (2, (8, 13), (12, 13), ("m", "N"), "m/N"),
}


@pytest.mark.parametrize("kind", list(KIND_CASES))
@pytest.mark.parametrize(
    "fields, rule",
    [
        ("right types", "type field"),
        ("uninformative types", "unit label"),
        ("wrong types", "physics"),
        ("none", "physics"),
    ],
)
def test_kind_read_back_as_the_same_accelerance(tmp_path, kind, fields, rule):
    n, right, wrong, labels, whole = KIND_CASES[kind]
    options = {
        "right types": {"types": right},
        "uninformative types": {"types": (1, 0), "labels": (whole, "NONE")},
        "wrong types": {"types": wrong, "labels": labels},  # type fields and labels disagree: physics decides
        "none": {"types": (0, 0)},
    }[fields]
    stored = grid() / (2j * np.pi * FREQUENCIES) ** n
    contents = read_uff(write(tmp_path / "kind.uff", full_set(stored, **options)))
    assert {(f.kind, f.rule) for f in contents.frfs} == {(kind, rule)}
    assert len(contents.warnings) == (9 if rule == "physics" else 0)
    assert_close(to_recording(contents).frf, grid(), 1e-9)


def test_binary_and_uneven_records_from_pyuff(tmp_path):
    """pyuff's 58b states half the bytes of complex data and writes an uneven abscissa in doubles."""
    f = np.geomspace(3.0, 200.0, 60)
    contents = read_uff(write(tmp_path / "b.uff", full_set(grid(f), f=f, binary=1, abscissa_spacing=0)))
    found = to_recording(contents)
    np.testing.assert_array_equal(found.frequencies, f)
    assert_close(found.frf, grid(f), 1e-15)


@pytest.mark.parametrize(
    "system, labels, length, frf_factor",
    [
        (
            (7, "Inch (pound f)", 39.37007874015748, 0.2248089430997105),
            ("NONE", "NONE"),
            0.0254,
            0.0254 / 4.4482216152605,
        ),
        (None, ("g", "lbf"), 1.0, 9.80665 / 4.4482216152605),
        ((5, "mm (milli newton)", 1000.0, 1000.0), ("mm/s^2", "N"), 0.001, 0.001),
        ((5, "mm (milli newton)", 1000.0, 1000.0), ("NONE", "NONE"), 0.001, 1.0),
    ],
    ids=["in-lbf-164", "g-lbf-labels", "mm-labels", "mm-mN-164"],
)
def test_units_read_back_in_si(tmp_path, system, labels, length, frf_factor):
    before = []
    if system:
        code, description, length_factor, force_factor = system
        before.append(
            pyuff.prepare_164(
                units_code=code,
                units_description=description,
                temp_mode=2,
                length=length_factor,
                force=force_factor,
                temp=1.0,
                temp_offset=273.15,
            )
        )
    functions = full_set(grid(), labels=labels)
    path = tmp_path / "units.uff"
    pyuff.UFF(str(path)).write_sets([*before, nodes(scale=1.0 / length), *functions], mode="overwrite")
    found = to_recording(read_uff(path))
    points = [POINTS[node] for node, _ in SENSORS]
    np.testing.assert_allclose(found.sensors.points, points, rtol=1e-5, atol=1e-12)  # 15 holds 6 digits
    assert_close(found.frf, grid() * frf_factor, 1e-11)


def test_unit_labels():
    assert units("(1/N)*(m/s²)") == (1.0, (1, -2, -1)) and units("(m/s)/N") == (1.0, (1, -1, -1))
    assert units("g/lbf")[0] == pytest.approx(9.80665 / 4.4482216152605) and units("in/s2")[1] == (1, -2, 0)
    assert units("NONE") == (1.0, (0, 0, 0)) and units("Pa") is None


# ---- coordinate systems written by hand: 18 with a chain of references, 2420


SYSTEMS_18 = """    -1
    18
         5         0         0         8         1
TURNED
  1.00000e+00  2.00000e+00  3.00000e+00  1.00000e+00  3.00000e+00  3.00000e+00
  1.00000e+00  2.00000e+00  4.00000e+00
         6         0         5         8         1
IN FIVE
  1.00000e+00  0.00000e+00  0.00000e+00  1.00000e+00  0.00000e+00  1.00000e+00
  1.00000e+00 -1.00000e+00  1.00000e+00
    -1
"""
SYSTEMS_2420 = """    -1
  2420
         1
PART
         6         0         8
IN FIVE
  0.0000000000000000D+00  0.0000000000000000D+00  1.0000000000000000D+00
  0.0000000000000000D+00 -1.0000000000000000D+00  0.0000000000000000D+00
  1.0000000000000000D+00  0.0000000000000000D+00  0.0000000000000000D+00
  1.0000000000000000D+00  3.0000000000000000D+00  3.0000000000000000D+00
    -1
"""


@pytest.mark.parametrize("systems", [SYSTEMS_18, SYSTEMS_2420], ids=["18", "2420"])
def test_nodes_in_local_systems(tmp_path, systems):
    """System 5: origin (1, 2, 3), axes +Y, -X, +Z. System 6, defined in 5: origin (1, 0, 0), x along 5's z, z along
    5's -y; globally origin (1, 3, 3), axes +Z, -Y, +X, as the 2420 copy says. Node 1 is defined in system 6."""
    path = tmp_path / "systems.uff"
    path.write_text(systems)
    pyuff.UFF(str(path)).write_sets(
        [
            pyuff.prepare_15(node_nums=[1], def_cs=[6], disp_cs=[6], color=[8], x=[0.5], y=[0.0], z=[-0.25]),
            *[function((1, c), (r, 1), grid()[0, 0]) for c in (1, 2, -3) for r in (2, 3, 4)],
            pyuff.prepare_15(
                node_nums=[2, 3, 4],
                def_cs=[0] * 3,
                disp_cs=[0] * 3,
                color=[8] * 3,
                x=[0.0, 1.0, 0.0],
                y=[1.0, 0.0, 0.0],
                z=[0.0, 0.0, 1.0],
            ),
        ],
        mode="add",
    )
    found = to_recording(read_uff(path))
    axes = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]]).T  # columns: 6's x, y, z, global
    np.testing.assert_allclose(found.sensors.points[0], np.array([1.0, 3.0, 3.0]) + axes @ [0.5, 0.0, -0.25])
    np.testing.assert_allclose(found.sensors.directions, [axes[:, 0], axes[:, 1], -axes[:, 2]], atol=1e-12)
    np.testing.assert_array_equal(found.sensors.triaxial, [0, 0, 0])


# ---- bad input: one-line MasslineError naming the problem


def truncated(tmp_path):
    write_uff(tmp_path / "t.uff", virtual_recording(), binary=True)
    data = (tmp_path / "t.uff").read_bytes()
    return tmp_path / "t.uff", data[: len(data) * 2 // 3]


def truncated_ascii(tmp_path):
    write_uff(tmp_path / "t.uff", virtual_recording())
    data = (tmp_path / "t.uff").read_bytes()
    return tmp_path / "t.uff", data[: len(data) - 500]


def with_nan(tmp_path):
    """FRF 2 with NaN at lines 6-8, as a damaged export holds them (the writer leaves a recording's NaN lines out
    and pyuff's writes them as 0): its values, two complex per E20.12 line, edited in the text."""
    path = tmp_path / "nan.uff"
    write_uff(path, virtual_recording())
    lines = path.read_text().splitlines(keepends=True)
    start = [k for k, line in enumerate(lines) if line == "    58\n"][1] + 12  # FRF 2's first line of values
    for row, fields in ((start + 2, (2,)), (start + 3, (0, 2))):
        values = [lines[row][20 * f : 20 * f + 20] for f in range(4)]
        lines[row] = "".join(f"{'NaN':>20s}" if f in fields else v for f, v in enumerate(values)) + "\n"
    path.write_text("".join(lines))
    return path, None


def file_of(functions):
    def build(tmp_path):
        return write(tmp_path / "bad.uff", functions), None

    return build


def text(content):
    return lambda tmp_path: (tmp_path / "bad.uff", content.encode())


GRID = grid()
ALL = full_set(GRID)
BAD = {
    "missing file": (lambda tmp_path: (tmp_path / "nowhere.uff", None), "does not exist"),
    "not a UFF": (text("frequency,re,im\n1,2,3\n"), "holds no Universal File datasets"),
    "truncated binary": (truncated, "is truncated: its dataset 58 starting at line"),
    "truncated ascii": (truncated_ascii, "is truncated"),
    "unreadable dataset": (
        text("    -1\n    15\n         1         0         0         8  1.0e+00  x.y  0.0\n    -1\n"),
        "dataset 15 at line 1 is unreadable",
    ),
    "geometry only": (file_of([]), r"holds no FRFs \(datasets found: 15\): it is a geometry file"),
    "node without coordinates": (
        file_of([*ALL[:8], function((57, 3), EXCITERS[2], GRID[2, 2])]),
        "FRF 9 .* names response node 57, which has no coordinates in dataset 15/2411",
    ),
    "NaN": (with_nan, "FRF 2 .* has NaN or infinite values at 3 of 40 frequencies"),
    "rotation": (
        file_of([*ALL[:8], function(SENSORS[2], (13, 5), GRID[2, 2])]),
        r"reference 13:\+RY, not a translation",
    ),
    "scalar": (file_of([function((1, 0), e, GRID[0, 0]) for e in EXCITERS]), "response direction code 0"),
    "one exciter": (
        file_of([function(s, EXCITERS[0], GRID[0, 0]) for s in SENSORS]),
        r"1 reference \(exciter\) channel\(s\) \(11:\+X\): the method needs at least 3",
    ),
}


def bad_file(tmp_path, case):
    """The file of a BAD case, written into tmp_path, and the message it must give."""
    build, message = BAD[case]
    path, content = build(tmp_path)
    if content is not None:
        path.write_bytes(content)
    return path, message


def assert_command_refuses(command: str, tmp_path, case: str) -> None:
    """``massline COMMAND FILE`` on a BAD case's file exits 2 with one line naming the problem, no traceback."""
    from test_cli import cli

    path, words = bad_file(tmp_path, case)
    result = cli(command, path)
    assert result.returncode == 2, result.stderr
    assert re.search(words, result.stderr) and "Traceback" not in result.stderr
    assert result.stderr.count("\n") == 1


@pytest.mark.parametrize("case", list(BAD))
def test_bad_input_names_the_problem(tmp_path, case):
    path, message = bad_file(tmp_path, case)
    with pytest.raises(MasslineError, match=message) as error:
        to_recording(read_uff(path))
    assert "\n" not in str(error.value) and ": " in str(error.value)


def test_identical_repeat_is_dropped_with_a_warning(tmp_path):
    contents = read_uff(write(tmp_path / "repeat.uff", [*ALL, ALL[4]]))
    assert len(contents.frfs) == 9 and any("repeats FRF 5 exactly" in w for w in contents.warnings)
    assert_close(to_recording(contents).frf, GRID, 1e-11)


def test_tolerated_oddities_are_warned(tmp_path):
    """An unknown unit label and a num_pts that undercounts the data are read, and said."""
    functions = full_set(GRID)
    functions[0] = function(SENSORS[0], EXCITERS[0], GRID[0, 0], labels=("furlong/fortnight", "N"))
    path = write(tmp_path / "odd.uff", functions)
    path.write_text(path.read_text().replace("       395         1", "       390         1", 1))
    contents = read_uff(path)
    assert contents.frfs[0].rule == "type field" and len(contents.frfs[0].frequencies) == 395
    assert any("unit label 'furlong/fortnight' not understood" in w for w in contents.warnings)
    assert any("num_pts says 390 but the record holds 395 points" in w for w in contents.warnings)
    assert_close(to_recording(contents).frf, GRID, 1e-11)
