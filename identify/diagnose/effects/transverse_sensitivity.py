"""``transverse_sensitivity``: an accelerometer reading s·(a·t) besides a·d, t ⊥ d (mismatch notes §3 B1).

Simulated: every named channel reads ``size`` of the acceleration along a random t ⊥ its axis, as datasheets
allow (a few per cent). Knowingly not diagnosed (``model`` None): every fit estimates each channel's transverse
components under the datasheet's prior (:mod:`..effect_model`), and one beyond it is a ``sensor_direction``.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect, need, perpendicular


class TransverseSensitivity(Effect):
    name = "transverse_sensitivity"
    unit = "fraction"
    summary = "reads s·(a·t) besides a·d, t ⊥ d at random"
    model = None

    @classmethod
    def check_size(cls, size):
        super().check_size(size)
        need(abs(size) < 1.0, f"effect {cls.name}: a cross-axis reading of {size:g} of the main one is a broken "
             "accelerometer, not a datasheet's: give less than 1 (a few per cent, e.g. 0.03)")  # fmt: skip

    def simulate(self, state, lines, targets, rng):
        drawn = []
        for t in targets:
            t_dir = perpendicular(lines.directions[t], rng)
            state.sensor_vectors[t] += self.size * t_dir
            drawn.append(t_dir.tolist())
        return {"transverse": drawn} if drawn else {}
