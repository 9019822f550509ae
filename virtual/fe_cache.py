"""Elastic modes kept on disk between commands.

``massline plan``, ``simulate`` and ``report`` solve the same FE model of the same body: the same
surface, material, element size and number of modes give the same modes. The first command to solve
it keeps them in the cache folder; the others read them back instead of meshing and solving again
(about 7 s for a bundled body, minutes for a fine CAD part).

A model is filed under the SHA-256 of everything its modes depend on: the surface's vertices (m,
frame O xyz) and faces, Young's modulus, Poisson's ratio, density, the element size, the number of
modes, and the source of the modules that mesh and solve (:mod:`massline.virtual.elastic`,
:mod:`massline.virtual.tetmesh`), so a change to either is never served an old answer.

The folder is ``$MASSLINE_CACHE``, else ``$XDG_CACHE_HOME/massline``, else ``~/.cache/massline``;
``MASSLINE_CACHE=off`` turns the cache off. A cache that cannot be read or written is passed over:
the modes are then solved as without one.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

import massline.virtual.elastic as elastic
import massline.virtual.tetmesh as tetmesh
from massline.virtual.elastic import ElasticBody, ElasticModes, Material

if TYPE_CHECKING:  # a surface is hashed here, never read
    import trimesh

FORMAT = 1  # bump when the file's arrays change meaning


def cache_folder() -> Path | None:
    """The folder models are kept in, or None when the cache is off."""
    chosen = os.environ.get("MASSLINE_CACHE")
    if chosen is not None:
        return None if chosen.strip().lower() in ("", "off", "0", "no") else Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "massline"


def model_key(mesh: trimesh.Trimesh, material: Material, size: float | None, n: int) -> str:
    """SHA-256 (hex) of the surface, material, element size (m; None: the default mesh,
    :func:`.default_tetrahedra`), mode count and the FE code."""
    digest = hashlib.sha256(f"massline FE modes {FORMAT}".encode())
    digest.update(np.ascontiguousarray(mesh.vertices, dtype=np.float64).tobytes())
    digest.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
    size_key = -1.0 if size is None else size  # sizes are positive: −1 is the default mesh
    digest.update(np.array([material.youngs, material.poisson, material.density, size_key, n], dtype=float).tobytes())
    for module in (elastic, tetmesh):
        digest.update(Path(module.__file__).read_bytes())
    return digest.hexdigest()


def as_arrays(modes: ElasticModes) -> dict:
    """The arrays the modes are rebuilt from (:func:`from_arrays`): nodes (m), tetrahedra, element size (m),
    ω (rad/s) and shapes."""
    return {
        "points": modes.basis.mesh.p.T,
        "tets": modes.basis.mesh.t.T,
        "element_size": modes.element_size,
        "omega": modes.omega,
        "shapes": modes.shapes,
    }


def from_arrays(arrays, material: Material) -> ElasticModes:
    """The modes of :func:`as_arrays`' arrays (a dict or an open .npz), on their basis rebuilt."""
    body = ElasticBody(arrays["points"], arrays["tets"], material, float(arrays["element_size"]))
    return ElasticModes(np.asarray(arrays["omega"]), np.asarray(arrays["shapes"]), body.basis, body.element_size)


def load(path: Path, material: Material) -> ElasticModes | None:
    """The modes kept in ``path``, or None when there are none (or the file is unreadable)."""
    try:
        with np.load(path) as kept:
            return from_arrays(kept, material)
    except (OSError, KeyError, ValueError):
        return None


def store(path: Path, modes: ElasticModes) -> None:
    """Keep the modes in ``path``, written whole or not at all (a temporary file renamed into place)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".npz.part")
    except OSError:
        return
    try:
        with os.fdopen(handle, "wb") as file:
            np.savez(file, **as_arrays(modes))
        os.replace(temporary, path)
    except OSError:
        pass
    finally:
        Path(temporary).unlink(missing_ok=True)


def cached_modes(
    mesh: trimesh.Trimesh, material: Material, size: float | None, n: int, solve
) -> tuple[ElasticModes, bool]:
    """The modes of the model (``solve()`` when not kept, then kept), and whether they came from the cache."""
    folder = cache_folder()
    if folder is None:
        return solve(), False
    path = folder / f"{model_key(mesh, material, size, n)}.npz"
    kept = load(path, material) if path.is_file() else None
    if kept is not None:
        return kept, True
    modes = solve()
    store(path, modes)
    return modes, False
