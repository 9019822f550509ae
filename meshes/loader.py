"""Meshes in: a closed surface mesh, its units and material → nominal properties.

Every check a test engineer would want before trusting a CAD export happens
here, where the mesh enters: unreadable files, triangle soups, open surfaces,
inconsistent or inward winding, units that the mesh's size contradicts, and
densities typed in the wrong unit. Each raises :class:`MasslineError` with what
to do.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from massline.core.errors import MasslineError, param
from massline.core.rigid_body import RigidBody

if TYPE_CHECKING:
    import trimesh

UNITS = {"m": 1.0, "mm": 1e-3, "in": 0.0254}
PLAUSIBLE_SIZE_M = (0.01, 20.0)  # largest extent of a body one hangs on soft springs
TYPICAL_SIZE_M = 0.3
PLAUSIBLE_DENSITY = (10.0, 25_000.0)  # kg/m³: from rigid foams to tungsten alloys
MAX_SOLID_VOLUME_M3 = 1.0  # more solid material than any body hung on springs for this test
MAX_MASS_KG = 5000.0
MESH_SUFFIXES = {".stl", ".obj", ".ply", ".off", ".glb", ".gltf"}
ANY_UNITS = param("units", "'m'|'mm'|'in'", cli="m|mm|in")  # the units parameter, as an error names it


def _size_phrase(extents: np.ndarray, unit: str) -> str:
    return " × ".join(f"{e:.4g}" for e in extents) + f" {unit}"


def plausible_units(extents_native: np.ndarray) -> list[str]:
    """Units that would make the mesh a plausible test article, likeliest first."""
    size = float(np.max(extents_native))
    fits = [u for u, f in UNITS.items() if PLAUSIBLE_SIZE_M[0] <= size * f <= PLAUSIBLE_SIZE_M[1]]
    return sorted(fits, key=lambda u: abs(np.log(size * UNITS[u] / TYPICAL_SIZE_M)))


def check_units(extents_native: np.ndarray, units: str | None) -> float:
    """Metres per mesh unit; refuses units that the mesh's size contradicts."""
    guesses = plausible_units(extents_native)
    hint = f"it looks like {' or '.join(guesses)}" if guesses else "no unit makes it a plausible size"
    if units is None:
        raise MasslineError(
            f"the mesh does not say its units: pass {ANY_UNITS} "
            f"(it is {_size_phrase(extents_native, 'units')} across; {hint})"
        )
    if units not in UNITS:
        raise MasslineError(f"unknown unit {units!r}: use one of {', '.join(UNITS)}")
    size_m = float(np.max(extents_native)) * UNITS[units]
    lo, hi = PLAUSIBLE_SIZE_M
    if not lo <= size_m <= hi:
        raise MasslineError(
            f"with {param('units', repr(units), cli=units)} the mesh would be {size_m:.3g} m across, outside the "
            f"{lo:g}–{hi:g} m of a body tested on soft springs; {hint}: pass the right {param('units')}"
        )
    return UNITS[units]


def _topology_problem(mesh: trimesh.Trimesh) -> str | None:
    """What keeps the surface from enclosing a volume, or None."""
    if mesh.is_watertight:
        return None
    faces_per_edge = np.unique(mesh.edges_sorted, axis=0, return_counts=True)[1]
    shared = int(np.sum(faces_per_edge >= 2))
    open_edges = int(np.sum(faces_per_edge == 1))
    if shared == 0:
        return (
            f"it is a triangle soup: its {len(mesh.faces)} triangles share no edges, so it encloses no volume; "
            "export the part as a closed solid"
        )
    return (
        f"it is open: {open_edges} edges border a hole or a gap, so it encloses no volume; "
        "close the holes (e.g. trimesh.repair.fill_holes) or export the part as a solid"
    )


def read_mesh(path: str | Path) -> trimesh.Trimesh:
    """Read a surface mesh file as it is, without scaling; errors are one line."""
    path = Path(path)
    if path.is_dir():
        raise MasslineError(f"{path} is a folder, not a mesh file: give the STL, OBJ or PLY file inside it")
    if not path.is_file():
        raise MasslineError(f"mesh file {path} does not exist: check the path")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise MasslineError(f"{path.name}: unsupported mesh format {path.suffix!r}; use one of {sorted(MESH_SUFFIXES)}")
    import trimesh  # here, not at the top: a command that reads no mesh does not pay its ~0.5 s of imports

    try:
        with np.errstate(all="ignore"):  # NaN vertices are refused below
            mesh = trimesh.load(path, force="mesh")
    except Exception as err:  # trimesh raises many kinds for corrupt files
        raise MasslineError(f"{path.name} could not be read as a mesh ({err}); is the file complete?") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise MasslineError(f"{path.name} holds no triangles: export the part's surface")
    if not np.isfinite(mesh.vertices).all():
        raise MasslineError(f"{path.name} has NaN or infinite vertex coordinates: export it again")
    return mesh


def validate_solid(mesh: trimesh.Trimesh, name: str) -> None:
    """Raise unless the mesh bounds a solid with outward normals."""
    problem = _topology_problem(mesh)
    if problem:
        raise MasslineError(f"{name}: {problem}")
    if not mesh.is_winding_consistent:
        raise MasslineError(
            f"{name}: its faces are wound inconsistently (some normals point in, some out); "
            "repair it (e.g. trimesh.repair.fix_normals) and export again"
        )
    if mesh.volume <= 0:
        raise MasslineError(
            f"{name} is inside-out: its faces are wound inward, so its volume is negative "
            f"({mesh.volume:.4g}); flip the normals (e.g. trimesh.repair.fix_inversion) and export again"
        )
    if not encloses_a_solid(mesh):
        raise MasslineError(
            f"{name} folds through itself: its faces are closed and wound outward, yet the volume they bound has "
            "the centre of mass or the inertia no solid has; remove the self-intersections and export again"
        )


def encloses_a_solid(mesh: trimesh.Trimesh) -> bool:
    """Whether the mass properties the faces give (unit density) are those of a solid.

    A solid's centre of mass lies within its bounding box and its second moments about it,
    Σ = ½ tr(J) I − J (the body's covariance times its mass, J the inertia tensor about the CoG),
    are positive definite. A surface that passes through itself counts some regions negatively and
    can break either.
    """
    from trimesh.triangles import mass_properties

    props = mass_properties(mesh.triangles, density=1.0)
    lo, hi = mesh.bounds
    slack = 1e-9 * float(np.max(mesh.extents))
    inside = bool(np.all(props["center_mass"] >= lo - slack) and np.all(props["center_mass"] <= hi + slack))
    inertia = props["inertia"]
    moments = np.linalg.eigvalsh(0.5 * np.trace(inertia) * np.eye(3) - inertia)
    return inside and moments.min() > 0


def check_density(density: float, source: str = "") -> float:
    """The density (kg/m³) if it is that of a solid; ``source`` says where it came from."""
    lo, hi = PLAUSIBLE_DENSITY
    if not np.isfinite(density) or density <= 0:
        raise MasslineError(f"density {density} kg/m³ is not physical: give a positive number")
    if source:
        if not lo <= density <= hi:
            raise MasslineError(
                f"{source} gives a density of {density:.4g} kg/m³, which no solid has: check {param('units')} and "
                f"{param('mass')}"
            )
        return density
    if density < lo:
        raise MasslineError(
            f"density {density:g} kg/m³ is lighter than any solid; was it in g/cm³? (then pass {density * 1000:g})"
        )
    if density > hi:
        raise MasslineError(f"density {density:g} kg/m³ is heavier than any solid: check its unit (kg/m³)")
    return density


@dataclass(frozen=True, eq=False)
class BodyMesh:
    """A closed surface mesh in metres, in its own frame, with its material.

    ``density`` in kg/m³; the nominal properties are computed on demand.
    """

    mesh: trimesh.Trimesh
    density: float
    name: str = "mesh"
    units: str = "m"

    @cached_property
    def nominal(self) -> RigidBody:
        """Mass (kg), CoG (m) and inertia about the CoG (kg·m², tensor sign)."""
        from trimesh.triangles import mass_properties

        props = mass_properties(self.mesh.triangles, density=self.density)
        return RigidBody(props["mass"], props["center_mass"], props["inertia"])

    @property
    def volume(self) -> float:
        return float(self.mesh.volume)


def load_body(path: str | Path, units: str | None, density: float | None = None, mass: float | None = None) -> BodyMesh:
    """Read, check and scale a mesh to metres; material from density or total mass."""
    if (density is None) == (mass is None):
        raise MasslineError(
            f"give the material as exactly one of {param('density', cli='KG_M3')} or {param('mass', cli='KG')}"
        )
    mesh = read_mesh(path)
    name = Path(path).name
    validate_solid(mesh, name)
    native_extents = mesh.extents
    mesh = mesh.copy()
    mesh.apply_scale(check_units(native_extents, units))
    if mass is not None:
        if not np.isfinite(mass) or mass <= 0:
            raise MasslineError(f"mass {mass} kg is not physical: give a positive number")
        source = f"mass {mass:g} kg over the mesh volume {mesh.volume:.4g} m³"
        body = BodyMesh(mesh, check_density(mass / mesh.volume, source), name, units)
    else:
        body = BodyMesh(mesh, check_density(float(density)), name, units)
    if body.volume > MAX_SOLID_VOLUME_M3 or body.nominal.mass > MAX_MASS_KG:
        guesses = [u for u in plausible_units(native_extents) if u != units]
        hint = f"it looks like {' or '.join(guesses)}" if guesses else "check the mesh"
        raise MasslineError(
            f"with {param('units', repr(units), cli=units)} {name} would hold {body.volume:.3g} m³ of solid material "
            f"({body.nominal.mass:.4g} kg), more than a body tested on soft springs; {hint}: pass the right "
            f"{param('units')}"
        )
    return body
