"""Finite-element elastic modes of free-free solids against closed forms and the rigid-body mass matrix."""

import numpy as np
import pytest
import trimesh
from conftest import FIXTURE_MESHES

from massline.meshes import BUNDLED
from massline.core.errors import MasslineError
from massline.meshes.loader import load_body
from massline.virtual.elastic import ElasticBody, ElasticModes, Material
from massline.virtual.tetmesh import FEATURE_DOFS, default_size, default_tetrahedra, quadratic_dofs, tetrahedralise

STEEL = Material(210e9, 0.3, 7850.0)
ALUMINIUM = Material(70e9, 0.3, 2700.0)
EULER_BERNOULLI_FREE_FREE = np.array([4.730041, 7.853205])  # β_n L
LEISSA_FREE_SQUARE = np.array([13.468, 19.596, 24.270])  # ω a² √(ρh/D), ν = 0.3


def bundled(name):
    return load_body(BUNDLED[name].path, "m", BUNDLED[name].density)


def report(label, body, errors):
    """Print the mesh density and the relative errors (shown with ``pytest -s``)."""
    errors = np.array2string(np.asarray(errors), formatter={"float_kind": lambda e: f"{e:+.1e}"})
    print(f"{label}: h = {body.element_size * 1e3:.3g} mm, {body.n_dofs} DOF, relative errors {errors}")


@pytest.fixture(scope="module")
def bracket_body():
    body = bundled("bracket")
    return ElasticBody.from_mesh(body.mesh, Material(70e9, 0.33, body.density))


@pytest.fixture(scope="module")
def bracket_modes(bracket_body):
    return bracket_body.modes(6)


@pytest.fixture(scope="module")
def block():
    """A 0.1 × 0.05 × 0.02 m aluminium block centred on O, coarsely meshed."""
    return ElasticBody.from_mesh(trimesh.creation.box((0.1, 0.05, 0.02)), ALUMINIUM, 0.01)


@pytest.mark.parametrize("name", ["plate", "structure", "bracket"])
def test_tetrahedra_fill_the_surface_exactly(name):
    mesh = bundled(name).mesh
    points, tets = tetrahedralise(mesh, 0.02)
    edges = points[tets[:, 1:]] - points[tets[:, :1]]
    volumes = np.linalg.det(edges) / 6
    assert volumes.min() > 0
    assert volumes.sum() == pytest.approx(mesh.volume, rel=1e-13)


@pytest.mark.long  # two FE solves of a CAD part, timed against each other: the long tier
def test_a_part_whose_small_features_refine_the_default_mesh_is_graded_faster():
    """featuretype.STL (5 × 2.5 × 1.38 in, small holes and chamfers): at its default size netgen's default grading
    gives 78 000 DOF, a solve of most of a minute; graded faster it stays under FEATURE_DOFS and fills the solid
    as the default grading does (netgen fills this surface 0.9 % over its volume at either grading, not exactly
    as it fills the bundled bodies). The bundled bodies are meshed as before."""
    mesh = load_body(FIXTURE_MESHES / "featuretype.STL", "in", 2700.0).mesh
    size, points, tets = default_tetrahedra(mesh)
    finer = tetrahedralise(mesh, size)
    assert size == default_size(mesh)
    assert quadratic_dofs(*finer) > FEATURE_DOFS >= quadratic_dofs(points, tets)
    filled = [np.linalg.det(p[t[:, 1:]] - p[t[:, :1]]).sum() / 6 / mesh.volume for p, t in (finer, (points, tets))]
    assert filled[1] == pytest.approx(filled[0], abs=2e-3) and filled[1] == pytest.approx(1.0, abs=0.015)
    bracket = bundled("bracket").mesh
    np.testing.assert_array_equal(default_tetrahedra(bracket)[2], tetrahedralise(bracket, default_size(bracket))[1])


@pytest.mark.parametrize("name", ["plate", "structure", "bracket"])
def test_rigid_block_is_the_rigid_body_mass_matrix(name):
    body = bundled(name)
    fe = ElasticBody.from_mesh(body.mesh, Material(70e9, 0.3, body.density))
    expected = body.nominal.mass_matrix
    error = np.abs(fe.rigid_block - expected).max() / np.abs(expected).max()
    report(f"{name} rigid block", fe, np.array([error]))
    assert error < 1e-10


def test_free_free_beam_bending_matches_euler_bernoulli():
    # L/h = 80: the Timoshenko correction ½(β r)²(1 + E/κG) is 0.06 % and 0.16 % for the two modes.
    length, side = 0.8, 0.01
    body = ElasticBody.from_mesh(trimesh.creation.box((length, side, side)), STEEL)
    f = body.modes(4).frequencies_hz
    ei, rho_a = STEEL.youngs * side**4 / 12, STEEL.density * side**2
    expected = EULER_BERNOULLI_FREE_FREE**2 / (2 * np.pi * length**2) * np.sqrt(ei / rho_a)
    errors = f / np.repeat(expected, 2) - 1  # square section: each bending mode is a pair
    report("beam", body, errors)
    assert np.abs(errors).max() < 0.02


@pytest.mark.parametrize("thickness", [0.003, 0.006])
def test_free_free_square_plate_matches_leissa(thickness):
    # A converged run of this model (size 6 mm, 106 000 DOF, a/100) gives 13.433, 19.590, 24.262; the
    # beam-function Ritz upper bounds of Leissa (1973) and Barton (1951), 13.49, 19.79, 24.43, are up to 1 % higher.
    side = 0.3
    body = ElasticBody.from_mesh(trimesh.creation.box((side, side, thickness)), ALUMINIUM)
    omega = body.modes(3).omega
    flexural_rigidity = ALUMINIUM.youngs * thickness**3 / (12 * (1 - ALUMINIUM.poisson**2))
    parameter = omega * side**2 * np.sqrt(ALUMINIUM.density * thickness / flexural_rigidity)
    errors = parameter / LEISSA_FREE_SQUARE - 1
    report(f"plate a/{side / thickness:.0f}", body, errors)
    assert np.abs(errors).max() < 0.02


def test_modes_are_mass_normalised_and_orthogonal_to_rigid_motions(bracket_body, bracket_modes):
    phi, R = bracket_modes.shapes, bracket_body.rigid_fields
    M, K = bracket_body.mass, bracket_body.stiffness
    assert np.all(np.diff(bracket_modes.omega) > 0) and bracket_modes.omega[0] > 0
    assert np.abs(phi.T @ (M @ phi) - np.eye(6)).max() < 1e-10
    assert np.abs(phi.T @ (K @ phi) - np.diag(bracket_modes.omega**2)).max() < 1e-8 * bracket_modes.omega[-1] ** 2
    cosines = (R.T @ (M @ phi)) / np.sqrt(np.diag(bracket_body.rigid_block))[:, None]
    assert np.abs(cosines).max() < 1e-10


def test_shapes_at_surface_nodes_are_the_nodal_values(bracket_modes):
    basis = bracket_modes.basis
    nodes = basis.mesh.boundary_nodes()[::50]
    found = bracket_modes.shapes_at(basis.mesh.p[:, nodes].T)
    nodal = bracket_modes.shapes[basis.nodal_dofs[:, nodes]].transpose(2, 1, 0)
    assert found.shape == (6, len(nodes), 3)
    assert np.abs(found - nodal).max() < 1e-12 * np.abs(nodal).max()


def test_shapes_at_reproduce_rigid_motions_inside_on_and_just_outside(block):
    rng = np.random.default_rng(1)
    half = np.array([0.05, 0.025, 0.01])
    inside = rng.uniform(-half, half, (20, 3))
    on_faces = inside * np.where(np.arange(3) == rng.integers(0, 3, (20, 1)), half / np.abs(inside), 1.0)
    outside = on_faces * (1 + 1e-9 / np.abs(on_faces))
    points = np.vstack([inside, on_faces, outside])
    rigid = ElasticModes(np.zeros(6), block.rigid_fields, block.basis, block.element_size)
    q = rng.normal(size=6)
    error = np.abs(np.einsum("k,kpc->pc", q, rigid.shapes_at(points)) - (q[:3] + np.cross(q[3:], points)))
    assert error[:40].max() < 1e-12
    assert error[40:].max() < 1e-8  # evaluated on the surface, 1e-9 m away


def test_point_far_outside_the_solid_is_refused(block):
    modes = block.modes(1)
    with pytest.raises(MasslineError, match="outside the solid"):
        modes.shapes_at([[0.0, 0.0, 0.02]])


def test_open_surface_is_refused():
    box = trimesh.creation.box((0.1, 0.05, 0.02))
    with pytest.raises(MasslineError, match="open"):
        ElasticBody.from_mesh(trimesh.Trimesh(box.vertices, box.faces[:-2]), ALUMINIUM)


def test_separate_pieces_are_refused():
    box = trimesh.creation.box((0.1, 0.05, 0.02))
    pieces = trimesh.util.concatenate([box, box.copy().apply_translation([0.3, 0.0, 0.0])])
    with pytest.raises(MasslineError, match="separate pieces"):
        ElasticBody.from_mesh(pieces, ALUMINIUM, 0.02).modes(3)


@pytest.mark.parametrize(
    "youngs, poisson, density", [(0.0, 0.3, 2700.0), (70e9, 0.5, 2700.0), (70e9, -1.0, 2700.0), (70e9, 0.3, -1.0)]
)
def test_unphysical_material_is_refused(youngs, poisson, density):
    with pytest.raises(MasslineError):
        Material(youngs, poisson, density)
