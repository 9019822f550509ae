"""The flanged hub of tests/fixtures/meshes/flanged_hub.stl, in millimetres: a tube (OD 50, bore 30, 54 high) on a
flange (Ø100, 6 thick) with four Ø9 bolt holes on a Ø76 circle; 0.295 kg of aluminium (2700 kg/m³). A part a
technician meets: through-holes, a bore, a re-entrant corner where the tube meets the flange.

Run ``python tests/hub_mesh.py`` to write the fixture again (trimesh's booleans, through manifold3d).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

FIXTURE = Path(__file__).parent / "fixtures" / "meshes" / "flanged_hub.stl"
FLANGE = (50.0, 6.0)  # mm: radius, thickness
TUBE = (25.0, 15.0, 54.0)  # mm: outer radius, bore radius, height above the flange
BOLTS = (4.5, 38.0, 4)  # mm: hole radius, bolt circle radius, count
SECTIONS = 64  # facets around a circle


def hub() -> trimesh.Trimesh:
    """The hub as a closed mesh, mm, its flange's underside at z = 0 and its axis on z."""
    flange = trimesh.creation.cylinder(FLANGE[0], FLANGE[1], sections=SECTIONS)
    flange.apply_translation([0, 0, FLANGE[1] / 2])
    tube = trimesh.creation.cylinder(TUBE[0], TUBE[2], sections=SECTIONS)
    tube.apply_translation([0, 0, FLANGE[1] + TUBE[2] / 2])
    height = FLANGE[1] + TUBE[2]
    cutters = [trimesh.creation.cylinder(TUBE[1], 3 * height, sections=SECTIONS)]
    for k in range(BOLTS[2]):
        angle = np.pi / 4 + 2 * np.pi * k / BOLTS[2]
        hole = trimesh.creation.cylinder(BOLTS[0], 3 * FLANGE[1], sections=24)
        hole.apply_translation([BOLTS[1] * np.cos(angle), BOLTS[1] * np.sin(angle), FLANGE[1] / 2])
        cutters.append(hole)
    body = trimesh.boolean.union([flange, tube])
    return trimesh.boolean.difference([body, *cutters])


if __name__ == "__main__":
    mesh = hub()
    mesh.export(FIXTURE)
    print(f"{FIXTURE}: {len(mesh.faces)} faces, {mesh.volume * 2.7e-6:.4f} kg at 2700 kg/m³, watertight {mesh.is_watertight}")
