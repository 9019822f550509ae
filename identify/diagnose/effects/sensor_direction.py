"""``sensor_direction``: an accelerometer reading along an axis tilted off its label (mismatch notes §3 B1).

Simulated: the accelerometer turned by ``size`` degrees about a random axis ⊥ its own (a triaxial turns as one
block). Diagnosed: every channel's transverse components τ are estimated under the datasheet's prior; this
block widens that prior for one accelerometer to a mounting error's (``MISALIGNMENT``) and pays the Laplace
evidence's Occam factor for it instead of BIC's ln n (:mod:`..effect_fit`). Misalignment and transverse
sensitivity beyond the datasheet cannot be told apart by the data.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import (
    Block,
    Effect,
    accelerometers,
    moved_lines,
    need,
    perpendicular,
    pm,
    rotation,
)


class SensorDirection(Effect):
    name = "sensor_direction"
    unit = "degrees"
    summary = "accelerometer tilted about an axis ⊥ its own (a triaxial turns as one block)"
    widens_prior = True
    moves = "axis"
    rank = 2
    blind_range = (8.0, 20.0)

    @classmethod
    def check_size(cls, size):
        super().check_size(size)
        need(abs(size) <= 90.0, f"effect {cls.name}: a tilt of {size:g}° is past the perpendicular: give at most 90°"
             " (a reversed axis is a sign)")  # fmt: skip

    def simulate(self, state, lines, targets, rng):
        axes = []
        for t, block in accelerometers(lines, targets):
            axis = perpendicular(lines.directions[t], rng)
            state.sensor_vectors[block] = state.sensor_vectors[block] @ rotation(axis, np.radians(self.size)).T
            axes.append(axis.tolist())
        return {"axes": axes} if axes else {}

    @classmethod
    def blocks(cls, layout):
        """One per accelerometer (a plate's out-of-plane lines have no transverse readings to tilt)."""
        return [] if layout.planar else [Block(cls.name, k) for k in range(len(layout.groups))]

    @classmethod
    def values(cls, layout, target):
        return 0

    @classmethod
    def plausible(cls, result, block, v, tau):
        """Beyond any datasheet's cross-axis reading, under 45°."""
        tilt = np.linalg.norm(tau[result.problem.layout.channels(block)], axis=1).max()
        return bool(3 * result.problem.transverse < tilt < 1.0)

    @classmethod
    def parameters(cls, result, block):
        layout = result.problem.layout
        channels = list(layout.channels(block))
        _, tau, _ = result.parts
        T = layout.sensor_bases[channels]
        axis = layout.sensors.directions[channels] + np.einsum("nak,nk->na", T, tau[channels])
        angles = np.degrees(np.arctan(np.linalg.norm(tau[channels], axis=1)))
        spread = np.degrees(np.linalg.norm(result.tau_std[channels], axis=1))
        return {
            "angle_deg": angles.tolist(),
            "angle_std_deg": spread.tolist(),
            "effective_axis": (axis / np.linalg.norm(axis, axis=1)[:, None]).tolist(),
        }

    @classmethod
    def correct(cls, frf, sensors, exciters, finding):
        """Each channel's direction set to the axis it was found to read along."""
        for c, axis in zip(finding.channels, finding.parameters["effective_axis"]):
            sensors = moved_lines(sensors, c, direction=np.asarray(axis))
        return frf, sensors, exciters

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"{who} reads {pm(max(p['angle_deg']), max(p['angle_std_deg']))}° off its labelled axis: "
            "misalignment or transverse sensitivity beyond the datasheet (the data cannot tell them apart)"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"sensor {scene.sensor} is tilted {size:.1f}° off its labelled axis"
