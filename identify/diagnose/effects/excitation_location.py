"""``excitation_location``: a hammer hit landing off its labelled point (mismatch notes §3 C2).

Simulated: the hit moved ``size`` m along a random direction ⊥ it. Diagnosed: r_j' = r_j + U_j γ_j, γ in the
plane ⊥ the hit (along it an offset changes no moment); undone by moving the hit's point by the offset found.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import (
    Block,
    LocationEffect,
    block_values,
    mm,
    moved_lines,
    offset_parameters,
    perpendicular,
    pm,
)


class ExcitationLocation(LocationEffect):
    name = "excitation_location"
    unit = "m"
    perturbs = "exciter"
    summary = "hit δ away from its planned point, δ ⊥ d"
    rank = 11
    blind_range = (0.005, 0.02)

    def simulate(self, state, lines, targets, rng):
        offsets = []
        for t in targets:
            offset = self.size * perpendicular(lines.directions[t], rng)
            state.exciter_points[t] += offset
            offsets.append(offset.tolist())
        return {"offsets": offsets} if offsets else {}

    @classmethod
    def blocks(cls, layout):
        return [Block(cls.name, j) for j in range(len(layout.exciters))]

    @classmethod
    def displace(cls, lines, layout, target, v):
        lines.hits[target] += lines.U[target] @ v

    @classmethod
    def parameters(cls, result, block):
        v, sigma, _ = block_values(result, block)
        return offset_parameters(result.problem.layout.exciter_bases[block.target] @ v, np.linalg.norm(v), sigma)

    @classmethod
    def correct(cls, frf, sensors, exciters, finding):
        j = finding.exciter
        point = exciters.points[j] + np.asarray(finding.parameters["offset_m"])
        return frf, sensors, moved_lines(exciters, j, point=point)

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"{hit} landed {pm(p['distance_mm'], p['distance_std_mm'])} mm from its labelled point "
            f"(offset {mm(p['offset_m'], p['distance_std_mm'])})"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"hit {scene.hit} lands {1e3 * size:.1f} mm from its labelled point"
