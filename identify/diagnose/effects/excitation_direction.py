"""``excitation_direction``: a hammer hit going in off its labelled direction (mismatch notes §3 C1).

Simulated: the hit's direction turned by ``size`` degrees about a random axis ⊥ it. Diagnosed:
f_j = unit(d_j + U_j β_j), β in the plane ⊥ the labelled direction (none on a plate's out-of-plane hits);
undone by setting the hit's direction to the one found.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import (
    Block,
    Effect,
    block_values,
    moved_lines,
    need,
    perpendicular,
    pm,
    rotation,
)


class ExcitationDirection(Effect):
    name = "excitation_direction"
    unit = "degrees"
    perturbs = "exciter"
    summary = "hammer hit tilted away from the planned direction"
    moves = "axis"
    rank = 10
    blind_range = (8.0, 20.0)

    @classmethod
    def check_size(cls, size):
        super().check_size(size)
        need(abs(size) <= 90.0, f"effect {cls.name}: a tilt of {size:g}° is past the perpendicular: give at most 90°"
             " (a reversed axis is a sign)")  # fmt: skip

    def simulate(self, state, lines, targets, rng):
        directions = []
        for t in targets:
            turn = rotation(perpendicular(lines.directions[t], rng), np.radians(self.size))
            state.exciter_vectors[t] = turn @ state.exciter_vectors[t]
            directions.append(state.exciter_vectors[t].tolist())
        return {"directions": directions} if directions else {}

    @classmethod
    def blocks(cls, layout):
        return [] if layout.planar else [Block(cls.name, j) for j in range(len(layout.exciters))]

    @classmethod
    def displace(cls, lines, layout, target, v):
        lines.forces[target] = lines.forces[target] + lines.U[target] @ v
        lines.forces[target] /= np.linalg.norm(lines.forces[target])

    @classmethod
    def plausible(cls, result, block, v, tau):
        """Under 45°."""
        return bool(np.linalg.norm(v) < 1.0)

    @classmethod
    def parameters(cls, result, block):
        layout, j = result.problem.layout, block.target
        v, sigma, _ = block_values(result, block)
        f = layout.exciters.directions[j] + layout.exciter_bases[j] @ v
        angle = np.degrees(np.arccos(np.clip(f @ layout.exciters.directions[j] / np.linalg.norm(f), -1, 1)))
        return {
            "angle_deg": float(angle),
            "angle_std_deg": float(np.degrees(np.linalg.norm(sigma))),
            "direction": (f / np.linalg.norm(f)).tolist(),
        }

    @classmethod
    def correct(cls, frf, sensors, exciters, finding):
        direction = np.asarray(finding.parameters["direction"])
        return frf, sensors, moved_lines(exciters, finding.exciter, direction=direction)

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return f"{hit} went in {pm(p['angle_deg'], p['angle_std_deg'])}° off its labelled direction"

    @classmethod
    def concealed(cls, size, scene):
        return f"hit {scene.hit} goes in {size:.1f}° off its labelled direction"
