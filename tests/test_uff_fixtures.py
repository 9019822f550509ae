"""Real exporters' files (tests/fixtures/uff): every one is read, and says what it holds."""

import numpy as np
import pytest
import pyuff
from conftest import FIXTURE_UFF

from massline.core.errors import MasslineError
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff

FIXTURES = FIXTURE_UFF


def assert_close(found, expected, rtol):
    assert np.abs(found - expected).max() <= rtol * np.abs(expected).max()


# ---- real exporters' files: every file in the fixture folder is read, and says what it holds


def time_signal(contents):
    assert contents.frfs == () and contents.functions == ("time response",)
    return "holds no FRFs .*functions: time response ×1"


def geometry_per_node(contents):
    """Test.Lab gives every node its own system: node 1's local x, z are global -X, -Z; node 7's x, y, z are
    global +Z, -X, -Y."""
    assert len(contents.node_ids) == 36 and len(contents.systems) == 36 and contents.description == "AME_Test"
    k1, k7 = (list(contents.node_ids).index(n) for n in (1, 7))
    np.testing.assert_allclose(contents.node_frames[k1], np.diag([-1.0, 1.0, -1.0]), atol=1e-7)
    np.testing.assert_allclose(contents.node_frames[k7], [[0, -1, 0], [0, 0, -1], [1, 0, 0]], atol=1e-7)
    np.testing.assert_allclose(contents.node_points[k7], [-1.75, 0.0, 0.1])
    assert contents.node_systems[k7] == 7 and contents.warnings == []
    return r"holds no FRFs \(datasets found: 151, 164, 18, 15, 82\): it is a geometry file"


def heat_engine(contents):
    """Dataset 164 says mm (length factor 1000): coordinates come out in m."""
    assert len(contents.node_ids) == 10
    np.testing.assert_allclose(contents.node_points[0], [-0.1711755676269531, 0.1036403427124023, 0.13848291015625])
    return "holds no FRFs .*2411, 2412, 2414.*geometry file"


def measurement_accelerance(contents):
    """Three impact FRFs 0-1000 Hz, accelerance by their type fields (12 over 13), no geometry."""
    raw = pyuff.UFF(str(contents.path)).read_sets()
    assert [(f.response, f.reference) for f in contents.frfs] == [((1, 1), (n, 1)) for n in (1, 2, 3)]
    for frf, record in zip(contents.frfs, raw):
        assert (frf.kind, frf.rule, len(frf.frequencies)) == ("accelerance", "type field", 1001)
        assert (frf.frequencies[0], frf.frequencies[-1]) == (0.0, 1000.0)
        np.testing.assert_array_equal(frf.accelerance, record["data"])
    return "FRF 1 .* names response node 1, which has no coordinates in dataset 15/2411"


def non_ascii_header(contents):
    """Type field 'general' (1): the unit label '(1/N)*(m/s²)' (a latin-1 '²') decides accelerance."""
    (frf,) = contents.frfs
    assert (frf.kind, frf.rule, len(frf.frequencies), frf.response) == ("accelerance", "unit label", 6, (0, 0))
    return "has response direction code 0"


def frf_unv(contents):
    """Labelled 'Receptance' with unit label '(m/s)/N' (mobility): the labels contradict each other, the flat
    low-frequency massline (slope ~0) says accelerance. Directions only in the names; 2 points of padding."""
    (frf,) = contents.frfs
    assert (frf.kind, frf.rule, frf.response, frf.reference) == ("accelerance", "physics", (1, -3), (56, 3))
    assert len(frf.frequencies) == 1600 and frf.frequencies[-1] == 799.5
    assert any("padding" in w for w in contents.warnings) and any("'.1.Z-'" in w for w in contents.warnings)
    assert any("labels contradict" in w for w in contents.warnings)
    return "FRF 1 .* names response node 1, which has no coordinates"


def coherence_only(contents):
    assert contents.frfs == () and contents.functions == ("coherence",)
    assert any("has no FRF" in w for w in contents.warnings)
    return "holds no FRFs .*functions: coherence ×1"


def case_file(points, first, last):
    """UFFFiles' storage layouts: one accelerance FRF (type fields 12/13) from node 1 +X to node 22 +X."""

    def check(contents):
        (frf,) = contents.frfs
        assert (frf.kind, frf.rule, frf.response, frf.reference) == ("accelerance", "type field", (1, 1), (22, 1))
        assert len(frf.frequencies) == points and np.all(np.diff(frf.frequencies) > 0)
        np.testing.assert_allclose(frf.frequencies[[0, -1]], [first, last])
        return "names response node 1, which has no coordinates"

    return check


def case6_binary(contents):
    """Real doubles on an uneven abscissa of singles (pyuff 2.5 reads 1201 points): the values of case 1."""
    case1 = read_uff(FIXTURES / "ufffiles_dataset58_case1_binary.unv").frfs[0]
    np.testing.assert_array_equal(contents.frfs[0].accelerance, case1.accelerance)
    return case_file(1602, 10.0, 1000.0)(contents)


def systems_only(contents):
    assert list(contents.systems) == [1, 2, 3] and len(contents.node_ids) == 0
    np.testing.assert_allclose(contents.systems[1], [[-1, 0, 0], [0, 1, 0], [0, 0, -1], [-2.4, -0.95, 0]], atol=1e-7)
    return "datasets found: 18.*geometry file"


def nodes_only(contents):
    """289 nodes in system 1, which the file does not define: the global frame, with a warning."""
    assert len(contents.node_ids) == 289 and set(contents.node_systems) == {1}
    np.testing.assert_allclose(
        contents.node_points[0], [-4.3060027062892914e-02, -1.6987508861348033e-03, 0.70198684930801392]
    )
    assert any("system 1" in w for w in contents.warnings)
    return "datasets found: 2411.*geometry file"


def inch_pound(contents):
    """164 says in and lbf (39.37 in and 0.2248 lbf per SI unit): (in/s²)/lbf × 0.2248/39.37 is (m/s²)/N."""
    (frf,) = contents.frfs
    raw = pyuff.UFF(str(contents.path)).read_sets()[2]["data"]
    assert (frf.kind, frf.rule, len(frf.frequencies)) == ("accelerance", "type field", 10)
    assert_close(frf.accelerance, raw * 0.2248089430997105 / 39.37007874015748, 1e-15)
    return "names response node 1, which has no coordinates"


EXPECTED = {
    "pyuff_Sample_UFF58_ascii.uff": time_signal,
    "pyuff_Sample_UFF58b_bin.uff": time_signal,
    "pyuff_TestLab_161_164_18_15_82.uff": geometry_per_node,
    "pyuff_binary8byte.uff": time_signal,
    "pyuff_heat_engine_housing.uff": heat_engine,
    "pyuff_measurement_accelerance.uff": measurement_accelerance,
    "pyuff_non_ascii_header.uff": non_ascii_header,
    "ufffiles_dataset151_164_58_55.unv": inch_pound,
    "ufffiles_dataset18.unv": systems_only,
    "ufffiles_dataset2411.unv": nodes_only,
    "ufffiles_dataset58_FRF.unv": frf_unv,
    "ufffiles_dataset58_case1_binary.unv": case_file(1602, 0.0, 400.25),
    "ufffiles_dataset58_case4_ascii.unv": case_file(801, 10.0, 1000.0),
    "ufffiles_dataset58_case6_binary.unv": case6_binary,
    "ufffiles_dataset58_coh.unv": coherence_only,
}


@pytest.mark.parametrize(
    "path", sorted(p for p in FIXTURES.iterdir() if p.suffix in (".uff", ".unv")), ids=lambda p: p.name
)
def test_real_exporters_files(path):
    contents = read_uff(path)
    message = EXPECTED[path.name](contents)
    with pytest.raises(MasslineError, match=message) as error:
        to_recording(contents)
    assert "\n" not in str(error.value)
