"""Meshes in: closed forms for the bundled bodies, real CAD files, bad meshes caught."""

import numpy as np
import pytest
import trimesh
from conftest import FIXTURE_MESHES, bundled

from massline.meshes import BUNDLED
from massline.meshes.generate import BODIES, box_union_mesh
from massline.core.errors import MasslineError
from massline.meshes.loader import load_body


def closed_form(body):
    """Mass, CoG and J_G of disjoint solid boxes, written out by hand."""
    masses, centres, inertias = [], [], []
    for box in body.boxes:
        a, b, c = np.subtract(box.hi, box.lo)
        m = body.density * a * b * c
        masses.append(m)
        centres.append((np.add(box.hi, box.lo)) / 2)
        inertias.append(m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b]))
    M = sum(masses)
    G = sum(m * c for m, c in zip(masses, centres)) / M
    J = sum(
        Jb + m * ((c - G) @ (c - G) * np.eye(3) - np.outer(c - G, c - G)) for m, c, Jb in zip(masses, centres, inertias)
    )
    R = np.array(body.rotation)
    return M, R @ G + body.translation, R @ J @ R.T


@pytest.mark.parametrize("name", list(BUNDLED))
def test_bundled_meshes_match_closed_forms(name):
    mass, cog, J = closed_form(BODIES[name])
    nominal = bundled(name).nominal
    assert nominal.mass == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(nominal.cog, cog, rtol=0, atol=1e-12 * np.linalg.norm(cog))
    np.testing.assert_allclose(nominal.inertia_cog, J, rtol=0, atol=1e-12 * np.abs(J).max())


def test_plate_is_the_papers():
    p = bundled("plate").nominal
    assert p.mass == pytest.approx(0.567, rel=1e-12)
    np.testing.assert_allclose(p.cog, [0.0, 0.0636, 0.0], atol=1e-15)
    assert p.inertia_cog[0, 0] == pytest.approx(0.567 * (0.3**2 + 0.005**2) / 12, rel=1e-12)
    assert p.inertia_cog[1, 1] == pytest.approx(0.567 * (0.14**2 + 0.005**2) / 12, rel=1e-12)
    assert p.inertia_cog[2, 2] == pytest.approx(0.567 * (0.3**2 + 0.14**2) / 12, rel=1e-12)


def test_structure_is_of_the_papers_size_with_products_of_inertia():
    s = bundled("structure").nominal
    assert 3.5 < s.mass < 4.5
    off = s.inertia_cog[np.triu_indices(3, 1)]
    assert np.all(np.abs(off) > 1e-3 * np.abs(np.diag(s.inertia_cog)).max())


def test_bracket_has_oblique_distinct_principal_axes():
    b = bundled("bracket").nominal
    assert np.all(np.abs(b.principal_axes).max(axis=0) < 0.95)  # no axis within ~18° of a frame axis
    assert np.all(np.diff(b.principal_moments) / b.principal_moments[1:] > 0.05)


def test_box_mesh_in_mm_equals_metres(tmp_path):
    box = box_union_mesh(BODIES["structure"].boxes)
    box.apply_scale(1000.0)
    box.export(tmp_path / "s.stl")
    in_mm = load_body(tmp_path / "s.stl", "mm", density=7850).nominal
    np.testing.assert_allclose(in_mm.mass, bundled("structure").nominal.mass, rtol=1e-6)  # STL is float32


def test_mass_instead_of_density():
    a = load_body(BUNDLED["structure"].path, "m", mass=2.0).nominal
    b = bundled("structure").nominal
    assert a.mass == pytest.approx(2.0, rel=1e-12)
    np.testing.assert_allclose(a.inertia_cog, b.inertia_cog * 2.0 / b.mass, rtol=1e-12)


# Real CAD files: (file, units) that load, and what a wrong unit says.
REAL = [
    ("plate_holes.STL", "mm"),
    ("1002_tray_bottom.STL", "mm"),
    ("featuretype.STL", "in"),
    ("idler_riser.STL", "in"),
    ("angle_block.STL", "in"),
    ("ADIS16480.STL", "m"),
    ("busted.STL", "mm"),
]


@pytest.mark.parametrize("name,units", REAL)
def test_real_cad_meshes_load(name, units):
    body = load_body(FIXTURE_MESHES / name, units, density=2700)
    n = body.nominal
    assert n.mass > 0 and np.all(n.principal_moments > 0)
    assert np.all(body.mesh.bounds[0] <= n.cog) and np.all(n.cog <= body.mesh.bounds[1])


@pytest.mark.parametrize(
    "name,wrong,right",
    [
        ("plate_holes.STL", "m", "mm"),
        ("1002_tray_bottom.STL", "in", "mm"),
        ("featuretype.STL", "mm", "in"),
        ("featuretype.STL", "m", "in"),
        ("idler_riser.STL", "m", "in"),
        ("angle_block.STL", "m", "in"),
        ("ADIS16480.STL", "mm", "m"),
        ("ADIS16480.STL", "in", "m"),
    ],
)
def test_wrong_units_are_caught_and_the_likely_ones_named(name, wrong, right):
    with pytest.raises(MasslineError, match=f"it looks like {right}"):
        load_body(FIXTURE_MESHES / name, wrong, density=7850)


def test_missing_units_are_asked_for():
    with pytest.raises(MasslineError, match="does not say its units.*looks like mm"):
        load_body(FIXTURE_MESHES / "plate_holes.STL", None, density=2700)


def test_triangle_soup_is_refused():
    with pytest.raises(MasslineError, match="triangle soup"):
        load_body(FIXTURE_MESHES / "soup.stl", "m", density=1000)


def test_open_mesh_is_refused(tmp_path):
    mesh = trimesh.creation.box([0.1, 0.2, 0.3])
    mesh.update_faces(np.arange(len(mesh.faces)) != 0)
    mesh.export(tmp_path / "open.stl")
    with pytest.raises(MasslineError, match="it is open: 3 edges"):
        load_body(tmp_path / "open.stl", "m", density=1000)


def test_inside_out_mesh_is_refused(tmp_path):
    mesh = trimesh.creation.box([0.1, 0.2, 0.3])
    mesh.invert()
    mesh.export(tmp_path / "inverted.obj")
    with pytest.raises(MasslineError, match="inside-out.*negative"):
        load_body(tmp_path / "inverted.obj", "m", density=1000)


def test_inconsistent_winding_is_refused(tmp_path):
    mesh = trimesh.creation.box([0.1, 0.2, 0.3])
    faces = mesh.faces.copy()
    faces[0] = faces[0][::-1]
    trimesh.Trimesh(mesh.vertices, faces, process=False).export(tmp_path / "flipped.ply")
    with pytest.raises(MasslineError, match="wound inconsistently"):
        load_body(tmp_path / "flipped.ply", "m", density=1000)


def test_a_surface_folded_through_itself_is_refused(tmp_path):
    """A corner pushed through the opposite face: closed, wound outward, positive volume, yet no solid
    (its second moments about the CoG are not positive definite); a corner pulled out is a solid."""
    for corner, solid in [((0.5, 0.5, -2.0), False), ((3.0, 3.0, 3.0), True)]:  # in decimetres of a 1 dm cube
        mesh = trimesh.creation.box([0.1, 0.1, 0.1])
        mesh.vertices[np.argmax(mesh.vertices.sum(axis=1))] = np.array(corner) / 10
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
        mesh.export(tmp_path / "folded.obj")
        if solid:
            assert load_body(tmp_path / "folded.obj", "m", density=100).nominal.mass > 0
        else:
            with pytest.raises(MasslineError, match="folds through itself"):
                load_body(tmp_path / "folded.obj", "m", density=100)


@pytest.mark.parametrize(
    "content,match",
    [
        (b"solid x\nfacet normal 0 0", "could not be read|holds no triangles"),
        (b"", "could not be read|holds no triangles"),
    ],
)
def test_truncated_or_empty_files(tmp_path, content, match):
    (tmp_path / "bad.stl").write_bytes(content)
    with pytest.raises(MasslineError, match=match):
        load_body(tmp_path / "bad.stl", "m", density=1000)


def test_missing_file_and_format():
    with pytest.raises(MasslineError, match="does not exist"):
        load_body("nowhere.stl", "m", density=1000)
    with pytest.raises(MasslineError, match="unsupported mesh format"):
        load_body(__file__, "m", density=1000)


@pytest.mark.parametrize(
    "density,match", [(7.85, "g/cm³.*7850"), (-1.0, "not physical"), (1e6, "heavier"), (float("nan"), "not physical")]
)
def test_implausible_densities(density, match):
    with pytest.raises(MasslineError, match=match):
        load_body(BUNDLED["structure"].path, "m", density=density)


def test_material_must_be_given_once():
    with pytest.raises(MasslineError, match="exactly one"):
        load_body(BUNDLED["structure"].path, "m")
    with pytest.raises(MasslineError, match="exactly one"):
        load_body(BUNDLED["structure"].path, "m", density=1.0, mass=1.0)
