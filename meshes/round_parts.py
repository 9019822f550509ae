"""Round parts as a CAD exporter tessellates them: the bodies whose planning on curved surfaces is checked.

A stepped shaft, a cylinder, a hollow cylinder (a bearing housing) and a box with filleted edges, each with
``sections`` facets around a full circle (a CAD export's chordal tolerance). Lengths in metres; the axis of
the turned parts is z, from the origin. Steel unless a density is given.
"""

from __future__ import annotations

import numpy as np
import trimesh

STEEL = 7850.0  # kg/m³


def stepped_shaft(sections: int) -> trimesh.Trimesh:
    """Ø40 × 200 mm, then Ø30 × 120 mm, revolved about z."""
    profile = [(0.0, 0.0), (0.020, 0.0), (0.020, 0.200), (0.015, 0.200), (0.015, 0.320), (0.0, 0.320)]
    return trimesh.creation.revolve(np.array(profile), sections=sections)


def cylinder(sections: int) -> trimesh.Trimesh:
    """R 40 × 120 mm, centred on the origin."""
    return trimesh.creation.cylinder(radius=0.040, height=0.120, sections=sections)


def hollow_cylinder(sections: int) -> trimesh.Trimesh:
    """A bearing housing: bore Ø60, outside Ø100, 60 mm long, centred on the origin."""
    return trimesh.creation.annulus(r_min=0.030, r_max=0.050, height=0.060, sections=sections)


def filleted_box(sections: int) -> trimesh.Trimesh:
    """120 × 80 × 60 mm with every edge and corner rounded to R 10 mm: the hull of a sphere at each corner of
    the 100 × 60 × 40 mm core."""
    corners = np.array(np.meshgrid([-0.05, 0.05], [-0.03, 0.03], [-0.02, 0.02])).T.reshape(-1, 3)
    ball = trimesh.creation.uv_sphere(0.010, count=[max(sections // 2, 4), sections]).vertices
    return trimesh.convex.convex_hull(np.vstack([ball + c for c in corners]))


PARTS = {"shaft": stepped_shaft, "cylinder": cylinder, "hollow cylinder": hollow_cylinder, "filleted box": filleted_box}
