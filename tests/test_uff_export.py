"""Universal File export of a virtual test: what plain pyuff reads back is what was written."""

import numpy as np
import pytest
import pyuff
from scipy.spatial.transform import Rotation

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.uff import writer as uff_export
from massline.uff.grid import to_recording
from massline.uff.node_layout import line_from_code, uff_layout
from massline.uff.reader import read_uff
from massline.uff.recording import Recording
from massline.uff.units import INCH, LBF, G
from massline.uff.writer import write_uff

ROTATED = Rotation.from_euler("xyz", [20, -35, 50], degrees=True).as_matrix()
LEFT_HANDED = Rotation.from_euler("zyx", [-70, 15, 110], degrees=True).as_matrix() @ np.diag([1.0, 1.0, -1.0])
SHARED_POINT = [0.1, 0.2, 0.3]


def sensors() -> Lines:
    """Global-axis lines (two at one point), two oblique lines, a rotated and a left-handed triaxial."""
    points = [SHARED_POINT, SHARED_POINT, [-0.2, 0.05, 0.1], [0.3, -0.1, 0.2], [0.0, 0.4, -0.1]]
    directions = [[1, 0, 0], [0, 0, -1], [0, -1, 0], [1, 2, -0.5], [0.1, -0.2, -1]]
    points += [[-0.15, -0.25, 0.05]] * 3 + [[0.22, 0.31, -0.12]] * 3
    directions += list(ROTATED.T) + list(LEFT_HANDED.T)
    return Lines(points, directions, [-1] * 5 + [0, 0, 0, 1, 1, 1])


def exciters() -> Lines:
    """Oblique hits, and one at sensor 1's point along global +y."""
    return Lines([[0.25, 0.1, -0.05], SHARED_POINT, [-0.3, 0.0, 0.15]], [[0.3, -0.4, 0.866], [0, 1, 0], [-1, 0.2, 0.1]])


def recording(frequencies=None, s=None, e=None) -> Recording:
    s, e = s or sensors(), e or exciters()
    f = 2.0 + 0.25 * np.arange(40) if frequencies is None else np.asarray(frequencies)
    rng = np.random.default_rng(7)
    shape = (len(s), len(e), len(f))
    frf = (rng.normal(size=shape) + 1j * rng.normal(size=shape)) * 10.0 ** rng.uniform(-4, 2, size=shape[:2])[..., None]
    return Recording(f, frf, s, e, coherence=rng.uniform(0.5, 1.0, size=shape), description="rig 3, run 12")


def frame_18(origin, x_point, xz_point):
    """A dataset-18 system's axes (columns) from its origin, a point on +x and a point on the +xz plane."""
    x = (x_point - origin) / np.linalg.norm(x_point - origin)
    z = xz_point - origin - ((xz_point - origin) @ x) * x
    z /= np.linalg.norm(z)
    return np.column_stack([x, np.cross(z, x), z])


def read_back(path):
    """Node points, node frames and the 58 records, as plain pyuff reads them."""
    frames, points, systems, functions, types = {0: np.eye(3)}, {}, {}, [], []
    for s in pyuff.UFF(str(path)).read_sets():
        types.append(s["type"])
        if s["type"] == 18:
            for n, *definition in zip(s["cs_num"], s["ref_o"], s["x_point"], s["xz_point"]):
                frames[int(n)] = frame_18(*definition)
        elif s["type"] == 2420:
            frames.update({int(n): m[:3].T for n, m in zip(s["CS_sys_labels"], s["CS_matrices"])})
        elif s["type"] in (15, 2411):
            for n, cs, *xyz in zip(s["node_nums"], s["disp_cs"], s["x"], s["y"], s["z"]):
                points[int(n)], systems[int(n)] = np.array(xyz), int(cs)
        elif s["type"] == 58:
            functions.append(s)

    def line(node, code):
        return points[node], line_from_code(points[node], frames[systems[node]], code)

    return types, line, functions


def match(lines: Lines, point, direction, point_tol, direction_tol) -> int:
    """The one line through ``point`` along ``direction``."""
    found = np.flatnonzero(
        (np.abs(lines.points - point).max(axis=1) <= point_tol)
        & (np.abs(lines.directions - direction).max(axis=1) <= direction_tol)
    )
    assert len(found) == 1, (point, direction)
    return int(found[0])


# nodes dataset, binary: coordinate and direction tolerances of the geometry records, value tolerance of 58
CASES = {
    (15, False): (5e-6, 1e-5, 1e-12),  # 15/18 are E13.5 (6 digits), ascii 58 is E20.12
    (15, True): (5e-6, 1e-5, 0.0),
    (2411, False): (0.0, 1e-9, 1e-12),  # 2411/2420 are D25.16
    (2411, True): (0.0, 1e-9, 0.0),
}


@pytest.mark.parametrize("nodes_dataset, binary", list(CASES))
def test_round_trip(tmp_path, nodes_dataset, binary):
    point_tol, direction_tol, value_tol = CASES[nodes_dataset, binary]
    rec = recording()
    path = tmp_path / "test.uff"
    write_uff(path, rec, binary=binary, nodes_dataset=nodes_dataset)
    types, line, functions = read_back(path)
    assert types[:4] == [151, 164, 18 if nodes_dataset == 15 else 2420, nodes_dataset]
    seen = {uff_export.FRF: set(), uff_export.COHERENCE: set()}
    for record in functions:
        i = match(rec.sensors, *line(record["rsp_node"], record["rsp_dir"]), point_tol, direction_tol)
        j = match(rec.exciters, *line(record["ref_node"], record["ref_dir"]), point_tol, direction_tol)
        seen[record["func_type"]].add((i, j))
        written = rec.frf[i, j] if record["func_type"] == uff_export.FRF else rec.coherence[i, j]
        assert np.all(np.abs(record["data"] - written) <= value_tol * np.abs(written))
        np.testing.assert_array_equal(record["x"], rec.frequencies)
        assert record["binary"] == binary and record["abscissa_spacing"] == 1
        assert (record["abscissa_spec_data_type"], record["abscissa_axis_units_lab"]) == (18, "Hz")
        assert record["id4"].startswith(f"S{i + 1} ") and f" / E{j + 1} " in record["id4"]
        if record["func_type"] == uff_export.FRF:
            assert (record["ordinate_spec_data_type"], record["ordinate_axis_units_lab"]) == (12, "m/s^2")
            assert (record["orddenom_spec_data_type"], record["orddenom_axis_units_lab"]) == (13, "N")
            assert not binary or record["n_bytes"] == 16 * len(rec.frequencies)
    pairs = {(i, j) for i in range(len(rec.sensors)) for j in range(len(rec.exciters))}
    assert seen == {uff_export.FRF: pairs, uff_export.COHERENCE: pairs}
    assert len(functions) == 2 * len(pairs)


def test_layout_nodes_and_codes():
    s, e = sensors(), exciters()
    layout = uff_layout(s, e)
    assert layout.sensor_nodes[0] == layout.sensor_nodes[1] and list(layout.sensor_codes[:3]) == [1, -3, -2]
    assert layout.sensor_codes[4] == -3  # a tilted "-z" sensor keeps its code, in a frame near the identity
    assert list(layout.sensor_codes[5:8]) == [1, 2, 3] and list(layout.sensor_codes[8:]) == [1, 2, -3]
    assert len(set(layout.sensor_nodes[5:8])) == 1 and len(set(layout.sensor_nodes[8:])) == 1
    assert layout.exciter_nodes.min() == 101 and layout.exciter_codes[1] == 2
    assert layout.sensor_nodes.max() == 6 and list(layout.exciter_nodes) == [101, 102, 103]
    np.testing.assert_allclose(np.linalg.det(layout.node_frames), 1.0, atol=1e-12)
    np.testing.assert_allclose(
        layout.node_frames @ layout.node_frames.transpose(0, 2, 1), np.eye(3)[None].repeat(9, 0), atol=1e-12
    )
    global_nodes = layout.node_ids[layout.node_systems == 0]
    assert set(global_nodes) == {1, 2, 102}
    for lines, nodes, codes in [
        (s, layout.sensor_nodes, layout.sensor_codes),
        (e, layout.exciter_nodes, layout.exciter_codes),
    ]:
        for k in range(len(lines)):
            np.testing.assert_allclose(layout.direction(nodes[k], codes[k]), lines.directions[k], atol=1e-12)


def test_line_from_code():
    frame = ROTATED
    np.testing.assert_array_equal(line_from_code(np.zeros(3), frame, -2), -frame[:, 1])
    with pytest.raises(ValueError, match="direction code 4"):
        line_from_code(np.zeros(3), frame, 4)


def test_bad_layouts_raise():
    skewed = Lines([[0, 0, 0]] * 3, [[1, 0, 0], [0.1, 1, 0], [0, 0, 1]], [0, 0, 0])
    with pytest.raises(ValueError, match="not mutually orthogonal"):
        uff_layout(skewed, exciters())
    with pytest.raises(ValueError, match="same line"):
        uff_layout(Lines.along_axes([[0, 0, 0], [0, 0, 0]], [2, 2]), exciters())
    with pytest.raises(ValueError, match="not along a global axis"):
        uff_layout(sensors(), exciters(), node_systems=False)


def test_global_lines_need_no_systems(tmp_path):
    s = Lines.triaxials([[0.1, 0.0, 0.0]]) + Lines.along_axes([[0.0, 0.2, 0.0]], [2])
    e = Lines.along_axes([[0.1, 0.0, 0.0]], [0])
    path = tmp_path / "global.uff"
    write_uff(path, recording(s=s, e=e), node_systems=False, nodes_dataset=2411)
    types, line, functions = read_back(path)
    assert types == [151, 164, 2411] + [58] * 8
    assert [(f["rsp_node"], f["rsp_dir"], f["ref_node"], f["ref_dir"]) for f in functions[:4]] == [
        (1, 1, 101, 1),
        (1, 2, 101, 1),
        (1, 3, 101, 1),
        (2, 3, 101, 1),
    ]
    with pytest.raises(ValueError, match="node_systems=True"):
        write_uff(tmp_path / "oblique.uff", recording(), node_systems=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["global.uff"]


def test_uneven_axis(tmp_path):
    f = np.array([1.0, 1.5, 2.5, 4.0, 6.0, 8.5, 11.5])
    rec = recording(f, s=Lines.along_axes([[0, 0, 0], [0.1, 0, 0]], [2, 1]), e=Lines.along_axes([[0, 0.1, 0]], [0]))
    write_uff(tmp_path / "ascii.uff", rec)
    record = read_back(tmp_path / "ascii.uff")[2][0]
    assert record["abscissa_spacing"] == 0
    np.testing.assert_array_equal(record["x"], f)
    assert np.all(np.abs(record["data"] - rec.frf[0, 0]) <= 1e-12 * np.abs(rec.frf[0, 0]))
    # 58b, uneven, double precision: each point is the abscissa as a single, then the ordinate as doubles
    write_uff(tmp_path / "binary.uff", rec, binary=True)
    data = (tmp_path / "binary.uff").read_bytes()
    header = data[data.index(b"    58b") :].split(b"\n", 12)
    n_bytes = int(header[0].split()[4])
    assert n_bytes == 20 * len(f) and header[12][n_bytes:].startswith(b"    -1\n")
    points = np.frombuffer(header[12][:n_bytes], dtype=[("x", "<f4"), ("re", "<f8"), ("im", "<f8")])
    np.testing.assert_array_equal(points["x"], f)
    np.testing.assert_array_equal(points["re"] + 1j * points["im"], rec.frf[0, 0])


def test_millimetre_units(tmp_path):
    rec = recording()
    write_uff(tmp_path / "mm.uff", rec, units="MM", nodes_dataset=2411)
    sets = pyuff.UFF(str(tmp_path / "mm.uff")).read_sets()
    assert (sets[1]["units_code"], sets[1]["length"], sets[1]["force"]) == (5, 1000.0, 1000.0)
    layout = uff_layout(rec.sensors, rec.exciters)
    np.testing.assert_allclose(np.column_stack([sets[3]["x"], sets[3]["y"], sets[3]["z"]]), 1e3 * layout.node_points)
    frf = sets[4]
    assert (frf["ordinate_axis_units_lab"], frf["orddenom_axis_units_lab"]) == ("mm/s^2", "mN")
    np.testing.assert_allclose(frf["data"], rec.frf[0, 0], rtol=1e-12)


# units, acceleration: 164 code, FRF unit labels (numerator, denominator), file numbers per (m/s²)/N
UNIT_CASES = {
    ("SI", "length"): (1, ("m/s^2", "N"), 1.0),
    ("MM", "g"): (5, ("g", "N"), 1 / G),
    ("IN", "g"): (7, ("g", "lbf"), LBF / G),
    ("IN", "length"): (7, ("in/s^2", "lbf"), LBF / INCH),
}


@pytest.mark.parametrize("nodes_dataset", [15, 2411])
@pytest.mark.parametrize("binary", [False, True])
@pytest.mark.parametrize("units, acceleration", list(UNIT_CASES))
def test_unit_systems_round_trip(tmp_path, units, acceleration, binary, nodes_dataset):
    """What exporters write (g/N beside mm, g/lbf or in/s²/lbf beside inches) reads back as SI."""
    code, labels, factor = UNIT_CASES[units, acceleration]
    rec = recording()
    path = tmp_path / "units.uff"
    write_uff(path, rec, units=units, acceleration=acceleration, binary=binary, nodes_dataset=nodes_dataset)
    sets = pyuff.UFF(str(path)).read_sets()
    assert sets[1]["units_code"] == code
    frf = next(s for s in sets if s["type"] == 58 and s["func_type"] == uff_export.FRF)
    assert (frf["ordinate_axis_units_lab"], frf["orddenom_axis_units_lab"]) == labels
    assert (frf["ordinate_spec_data_type"], frf["orddenom_spec_data_type"]) == (12, 13)
    i, j = frf["rsp_node"], frf["ref_node"]  # sensor 1 at node 1 against hit 1 at node 101
    assert (i, j) == (1, 101)
    np.testing.assert_allclose(frf["data"], factor * rec.frf[0, 0], rtol=1e-11)
    contents = read_uff(path)
    found = to_recording(contents)
    assert contents.warnings == []
    np.testing.assert_allclose(found.frf, rec.frf, rtol=1e-11)
    np.testing.assert_allclose(found.coherence, rec.coherence, rtol=1e-11)
    digits = 5e-6 if nodes_dataset == 15 else 1e-15  # 15/18 hold 6 significant digits (E13.5), 2411/2420 exact
    for got, want in ((found.sensors, rec.sensors), (found.exciters, rec.exciters)):
        assert np.all(np.abs(got.points - want.points) <= digits * np.abs(want.points) + 1e-15)
        np.testing.assert_allclose(got.directions, want.directions, atol=4 * digits)


def test_refuses_to_overwrite(tmp_path):
    path = tmp_path / "test.uff"
    path.write_text("earlier test\n")
    with pytest.raises(FileExistsError, match="force=True"):
        write_uff(path, recording())
    assert path.read_text() == "earlier test\n"
    write_uff(path, recording(), force=True)
    assert pyuff.UFF(str(path)).get_n_sets() == 2 + 2 + 2 * 11 * 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["test.uff"]


@pytest.mark.parametrize("existing", [False, True])
def test_failure_leaves_no_file(tmp_path, monkeypatch, existing):
    path = tmp_path / "test.uff"
    if existing:
        path.write_text("earlier test\n")
    write_record = uff_export.dataset_58
    calls = []

    def failing(*args):
        calls.append(1)
        if len(calls) == 3:
            raise OSError("disk full")
        return write_record(*args)

    monkeypatch.setattr(uff_export, "dataset_58", failing)
    with pytest.raises(MasslineError, match=r"cannot write .*test\.uff \(disk full\)"):  # exit 2, one line
        write_uff(path, recording(), force=True)
    assert len(calls) == 3
    assert [p.name for p in tmp_path.iterdir()] == (["test.uff"] if existing else [])
    assert not existing or path.read_text() == "earlier test\n"


def test_rejects_bad_options(tmp_path):
    with pytest.raises(MasslineError, match="nodes_dataset"):
        write_uff(tmp_path / "a.uff", recording(), nodes_dataset=2412)
    with pytest.raises(MasslineError, match="units"):
        write_uff(tmp_path / "a.uff", recording(), units="FT")
    with pytest.raises(MasslineError, match="acceleration"):
        write_uff(tmp_path / "a.uff", recording(), acceleration="G")
    with pytest.raises(MasslineError, match="increase"):
        write_uff(tmp_path / "a.uff", recording([1.0, 3.0, 2.0]))
