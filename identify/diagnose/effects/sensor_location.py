"""``sensor_location``: an accelerometer glued off its labelled point (mismatch notes §3 B2).

Simulated: the accelerometer moved ``size`` m along a random direction ⊥ its axis (a triaxial moves as one).
Diagnosed: p_i' = p_i + T_i δ_i, δ in the plane ⊥ the axis (along it an offset cannot be seen), in 3-D for a
triaxial; undone by moving the channels' points by the offset found.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import (
    Block,
    LocationEffect,
    accelerometers,
    block_values,
    mm,
    moved_lines,
    offset_parameters,
    perpendicular,
    pm,
)


class SensorLocation(LocationEffect):
    name = "sensor_location"
    unit = "m"
    summary = "glued δ away from its planned point, δ ⊥ d"
    rank = 0
    blind_range = (0.005, 0.02)

    def simulate(self, state, lines, targets, rng):
        offsets = []
        for t, block in accelerometers(lines, targets):
            offset = self.size * perpendicular(lines.directions[t], rng)
            state.sensor_points[block] += offset
            offsets.append(offset.tolist())
        return {"offsets": offsets} if offsets else {}

    @classmethod
    def blocks(cls, layout):
        return [Block(cls.name, k) for k in range(len(layout.groups))]

    @classmethod
    def values(cls, layout, target):
        return 3 if len(layout.groups[target]) > 1 else 2

    @classmethod
    def displace(cls, lines, layout, target, v):
        channels = list(layout.groups[target])
        lines.points[channels] += v if len(v) == 3 else lines.T[channels[0]] @ v

    @classmethod
    def parameters(cls, result, block):
        layout = result.problem.layout
        v, sigma, _ = block_values(result, block)
        offset = v if len(v) == 3 else layout.sensor_bases[layout.channels(block)[0]] @ v
        return offset_parameters(offset, np.linalg.norm(offset), sigma)

    @classmethod
    def correct(cls, frf, sensors, exciters, finding):
        """Each channel's point moved by the offset found."""
        for c in finding.channels:
            sensors = moved_lines(sensors, c, point=sensors.points[c] + np.asarray(finding.parameters["offset_m"]))
        return frf, sensors, exciters

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"{who} sits {pm(p['distance_mm'], p['distance_std_mm'])} mm from its labelled point "
            f"(offset {mm(p['offset_m'], p['distance_std_mm'])}; along its axis an offset cannot be seen)"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"sensor {scene.sensor} sits {1e3 * size:.1f} mm from its labelled point"
