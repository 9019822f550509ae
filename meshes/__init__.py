"""massline.meshes — bundled meshes: the paper's plate, a 3-D steel structure, an oblique bracket.

Rebuild them with ``python -m massline.meshes.generate``. Each is in metres in
its own frame; ``BUNDLED`` gives its file, density and a description.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["BUNDLED", "Bundled"]


@dataclass(frozen=True)
class Bundled:
    file: str
    density: float  # kg/m³
    description: str
    youngs: float  # Pa
    poisson: float

    @property
    def path(self) -> Path:
        return Path(__file__).with_name(self.file)


BUNDLED = {
    "plate": Bundled(
        "plate.obj", 2700.0, "the paper's aluminium plate, 0.30 × 0.14 × 0.005 m (Table 1 frame)", 70e9, 0.33
    ),
    "structure": Bundled("structure.obj", 7850.0, "3-D steel structure of the paper's size (≈ 4 kg)", 210e9, 0.30),
    "bracket": Bundled("bracket.obj", 2700.0, "aluminium L-bracket with oblique principal axes", 70e9, 0.33),
}
